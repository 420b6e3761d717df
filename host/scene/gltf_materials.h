// glTF images, samplers and textures to Scene::textures, and materials to Scene::materials (index for
// index, so primitives keep the file's material indices).
#pragma once

#include <cstdint>

#include "scene/gltf_context.h"

namespace vkrt {

// Decodes every texture's image to 8-bit RGBA and reads its sampler. A texture without a core image
// source stays empty; a material that uses one fails.
void convertTextures(GltfContext& context);

// Reads every material, with the KHR_materials_* extensions vkrt supports.
void convertMaterials(GltfContext& context);

// The index of glTF's default material (white, metallic 1, roughness 1), appended on first use.
uint32_t defaultMaterial(GltfContext& context);

}  // namespace vkrt
