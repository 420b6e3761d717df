#include "support/render_both.h"

#include "bvh/triangle_bvh.h"
#include "gpu/gpu_renderer.h"

namespace vkrt::test {

FlatBvh bvhFor(const Scene& scene) {
    return buildSceneBvh(scene).flat;
}

RenderPair renderGpuAndCpu(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                           const Camera& camera, const RenderSettings& settings,
                           const std::string& shaderCacheDir) {
    GpuRenderOptions options;
    options.shaderCacheDir = shaderCacheDir;
    GpuRenderer gpu(context, scene, bvh, camera, settings, options);
    RenderPair pair;
    pair.gpu = gpu.render();
    pair.cpu = ReferenceRenderer(scene, bvh, camera, settings).render();
    return pair;
}

}  // namespace vkrt::test
