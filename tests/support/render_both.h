// One scene rendered by the GPU tracer and by the double-precision CPU reference with the same settings
// and seed, the pair every GPU-against-reference comparison starts from.
#pragma once

#include <string>

#include "bvh/flat_bvh.h"
#include "cpu/reference_renderer.h"
#include "gpu/vulkan_context.h"
#include "image/image.h"
#include "scene/scene.h"

namespace vkrt::test {

// The scene's BVH (triangles and analytic spheres), flattened as both renderers read it.
FlatBvh bvhFor(const Scene& scene);

struct RenderPair {
    RenderResult gpu;
    RenderResult cpu;
};

RenderPair renderGpuAndCpu(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                           const Camera& camera, const RenderSettings& settings,
                           const std::string& shaderCacheDir);

// The mean of an image's red channel.
inline double meanRed(const Image& image) {
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels) sum += p.x;
    return sum / static_cast<double>(image.pixels.size());
}

}  // namespace vkrt::test
