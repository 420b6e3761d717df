// A glTF material's references to textures (textureInfo objects) as Scene texture slots.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/gltf_context.h"
#include "scene/scene.h"

namespace tinygltf {
class Value;
}  // namespace tinygltf

namespace vkrt {

// The materials that the rendered scene's nodes place (on their meshes' primitives, VKRT_sphere and
// VKRT_shape), read from a glTF document's JSON by the walk GltfConverter makes (sceneRoots, then children);
// nullopt where the document's nodes cannot be walked (the converter then says why). glTF's default material
// is not among them.
std::optional<std::set<int>> placedMaterials(const nlohmann::json& document);

// The textures that the slots vkrt reads name, read from a glTF document's JSON (the core slots of
// `materials`, every material when nullopt, and those of the extensions below; not KHR_materials_volume's
// thicknessTexture, nor those of extensions vkrt ignores): only their images are decoded.
std::set<int> texturesReadByMaterials(const nlohmann::json& document,
                                      const std::optional<std::set<int>>& materials);

// A material's texture slot: the glTF texture, its texture coordinate set and its KHR_texture_transform (an
// empty slot for index -1, and while GltfContext::readTextures is false). A texture that does not exist, or
// whose image is missing or did not decode, fails.
TextureSlot textureSlot(GltfContext& context, int index, int texCoord, const std::map<std::string, tinygltf::Value>& extensions,
                        const std::string& where);

// The same from a textureInfo object inside an extension (tinygltf leaves those as JSON values).
TextureSlot textureSlot(GltfContext& context, const tinygltf::Value& info, const std::string& where);

}  // namespace vkrt
