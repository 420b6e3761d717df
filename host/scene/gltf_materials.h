// glTF materials to Scene::materials (index for index, so primitives keep the file's material indices), and
// the textures they read, with their images and samplers, to Scene::textures.
#pragma once

#include <cstdint>

#include "scene/gltf_context.h"

namespace vkrt {

// Reads every material, with the KHR_materials_* extensions vkrt supports. Its texture slots name the file's
// textures, whose images textureSlot checked, until convertTextures.
void convertMaterials(GltfContext& context);

// The textures the materials' slots name, each with its sampler read, as Scene::textures in the file's order;
// the slots are renumbered to them. Textures no slot names are left out. Each image is expanded to 8-bit RGBA
// once, its texels shared by the textures that show it.
void convertTextures(GltfContext& context);

// The index of glTF's default material (white, metallic 1, roughness 1), appended on first use.
uint32_t defaultMaterial(GltfContext& context);

}  // namespace vkrt
