// The scene's materials, lights and textures in the form the shared shading code reads (shaders/*.h), made
// once here for both renderers: the CPU reference reads these structs directly, the GPU packs them into its
// buffers (host/gpu/gpu_scene.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "camera.h"
#include "common/large_buffer.h"
#include "punctual_light.h"
#include "scene/scene.h"
#include "shared.h"
#include "surface_response.h"

namespace vkrt {

// The material in the shared code's form. Its texture slots, of `textures`, are appended to `bindings` (the
// GPU's GpuTextureBinding table) and named by their index there; a slot without a texture is -1.
shading::SurfaceMaterial surfaceMaterial(const Material& material, const std::vector<Texture>& textures,
                                         std::vector<gpu::GpuTextureBinding>& bindings);

shading::PunctualLightParams punctualLightParams(const PunctualLight& light);

// The camera as shaders/camera.h reads it, for an image of width x height pixels, in a scene within
// `sceneBounds` (a thin lens far wider than them starts its rays nearer; none when the box is empty).
shading::CameraFrame cameraFrame(const Camera& camera, const Aabb& sceneBounds, int width, int height);

// Every texture's RGBA8 texels in one array (red in the lowest byte, rows top to bottom), each texture
// described by where its texels start, its size and its sampler (shaders/texture_sampling.h). Textures that
// show one image in one colour space share their texels.
struct PackedTextures {
    std::vector<gpu::GpuTexture> textures;
    HugePageVector<uint32_t> texels;  // often a hundred MB and more: on huge pages
};

PackedTextures packTextures(const Scene& scene);

// packTextures in two steps, for a caller that keeps the texels elsewhere (the GPU's mapped buffer): the
// textures' descriptions, then their texels written to `texels` (packedTextureBytes of them).
std::vector<gpu::GpuTexture> describeTextures(const Scene& scene);
void writeTexels(const Scene& scene, const std::vector<gpu::GpuTexture>& textures, uint32_t* texels);

// The bytes packTextures' texels take: each image's RGBA8 texels with their mipmap levels, once for each
// colour space its textures read it in.
size_t packedTextureBytes(const Scene& scene);

}  // namespace vkrt
