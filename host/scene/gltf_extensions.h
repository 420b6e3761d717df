// glTF extensions vkrt reads: which are supported, KHR_materials_* values, EXT_mesh_gpu_instancing
// transforms, KHR_lights_punctual lights, VKRT_sphere spheres and the depth of field in camera extras.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>
#include <glm/glm.hpp>

#include "scene/gltf_context.h"

namespace vkrt {

// Fails on a required extension vkrt does not support; warns about an unsupported optional one.
void checkExtensions(GltfContext& context);

// The first extension a glTF document requires and vkrt does not support, read from its JSON directly: tinygltf
// may reject such a file (KHR_texture_basisu's images are in a format it cannot read) before the loader can
// name the reason.
std::optional<std::string> unsupportedRequiredExtension(const nlohmann::json& document);

// Reads KHR_materials_transmission, _ior, _volume into `material` and returns
// KHR_materials_emissive_strength (1 when absent).
float readMaterialExtensions(const GltfContext& context, const tinygltf::ExtensionMap& extensions,
                             const std::string& where, Material& material);

// EXT_mesh_gpu_instancing: one transform per instance, in the node's local space. `checkHeld` is given the
// bytes the reading holds at its peak before each allocation, and throws when they do not fit.
std::vector<glm::dmat4> instanceTransforms(
    const GltfContext& context, const tinygltf::Value& extension, const std::string& where,
    const std::function<void(uint64_t bytes, const std::string& what)>& checkHeld);

// KHR_lights_punctual on a node: appends the light it names, placed by `world`.
void addLight(GltfContext& context, const tinygltf::Value& extension, const glm::dmat4& world,
              const std::string& where);

// VKRT_sphere (docs/vkrt_sphere.md) on a node: the sphere placed by `world`.
Sphere placeSphere(GltfContext& context, const tinygltf::Value& extension, const glm::dmat4& world,
                   const std::string& where);

// vkrt's camera extras {"aperture": lens radius, "focusDistance": d}.
void readCameraExtras(GltfContext& context, const tinygltf::Value& extras, const std::string& where,
                      Camera& camera);

}  // namespace vkrt
