// The KHR_materials_* extensions that carry textures: each reads its factors and texture slots into a
// Material (gltf_extensions.cpp reads those with factors alone).
#pragma once

#include <algorithm>
#include <map>
#include <string>

#include "scene/gltf_context.h"
#include "scene/scene.h"

namespace tinygltf {
class Value;
}  // namespace tinygltf

namespace vkrt {

// A normal texture's scale, at most 1e6 either way: beyond it the mapped normal lies in the tangent plane to
// within 1e-6 rad, and beyond about 1.8e19 the GPU's single-precision length of it overflowed (the map was
// ignored there, and kept by the CPU).
inline float normalScaleOf(double scale) {
    return static_cast<float>(std::clamp(scale, -1e6, 1e6));
}

// KHR_materials_specular: the dielectric's specular reflection, scaled and tinted.
void readSpecular(GltfContext& context, const std::map<std::string, tinygltf::Value>& extensions, const std::string& where,
                  Material& material);

// KHR_materials_transmission's texture. KHR_materials_volume's thicknessTexture is unused, because a ray
// tracer measures the distance through the real geometry (docs/materials.md): only its index is checked.
void readExtensionTextures(GltfContext& context, const std::map<std::string, tinygltf::Value>& extensions,
                           const std::string& where, Material& material);

// KHR_materials_clearcoat: the coat's factor, roughness and normal, each with its texture.
void readClearcoat(GltfContext& context, const std::map<std::string, tinygltf::Value>& extensions,
                   const std::string& where, Material& material);

// KHR_materials_sheen: the sheen colour and roughness with their textures.
void readSheen(GltfContext& context, const std::map<std::string, tinygltf::Value>& extensions,
               const std::string& where, Material& material);

// KHR_materials_unlit.
void readUnlit(const std::map<std::string, tinygltf::Value>& extensions, Material& material);

}  // namespace vkrt
