// The unit square seen head-on, the canvas of the material tests: a textured quad filling an orthographic
// view, rendered on both devices.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/vulkan_context.h"
#include "scene/scene.h"
#include "support/render_both.h"

namespace vkrt::test {

// A texture of width x height texels given as RGBA8 words (red in the lowest byte), nearest filtering.
Texture textureOf(int width, int height, const std::vector<uint32_t>& texels);

// An exactly Lambertian material of grey albedo `albedo`: no metal, no specular reflection.
Material lambertian(float albedo);

// The unit square at z = 0 facing +z, texture coordinates equal to (x, 1 - y) (glTF: v runs down the image).
void addUnitSquare(Scene& scene, uint32_t material);

// An orthographic camera that sees exactly the unit square.
Camera squareCamera();

// An orthographic camera looking down -z at the unit sphere around the origin, which fills the film's inscribed
// disk.
Camera sphereCamera();

// The unit sphere around the origin as a mesh of `rings` x `segments` triangles of material `material`, with
// smooth normals and, when `tangents`, each corner's tangent frame pointing east (the way u grows on a
// VKRT_sphere: +y cross n, none at the poles) with w = 1 (the bitangent points north, up the texture).
void addUvSphereMesh(Scene& scene, int rings, int segments, uint32_t material, bool tangents);

// Lit by ambient radiance 1 alone (background 0.25): a Lambertian dielectric shows its albedo; one with a
// specular layer, (1 - F0) of it, plus F0 where the layer's lobe is not traced.
RenderSettings ambientOnly(int size);

// The unit square with `material` added to `scene` (which holds its textures and lights), on both devices.
RenderPair renderUnitSquare(const VulkanContext& context, Scene scene, const Material& material,
                            const RenderSettings& settings);

}  // namespace vkrt::test
