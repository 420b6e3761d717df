#include "gpu/gpu_raycaster.h"

#include <chrono>

#include <sys/resource.h>

#include "gpu/shader_compiler.h"
#include "gpu/vulkan_check.h"

namespace vkrt {

namespace {

// CPU time used by every thread of this process so far (lavapipe's workers included).
double processCpuMs() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto ms = [](const timeval& t) { return 1e3 * static_cast<double>(t.tv_sec) + 1e-3 * static_cast<double>(t.tv_usec); };
    return ms(usage.ru_utime) + ms(usage.ru_stime);
}

}  // namespace

GpuRaycaster::GpuRaycaster(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                           const std::string& shaderCacheDir, const std::vector<std::string>& extraDefines)
    : context_(context), data_(packScene(scene, bvh)) {
    sceneBuffers_ = std::make_unique<GpuSceneBuffers>(context, data_);
    gpu::SceneParams params{};
    params.primitiveCount = static_cast<uint32_t>(data_.primitives.size());
    sceneBuffers_->fillAddresses(params);
    params_ = GpuBuffer(context, &params, sizeof(params));
    const bool bound = sceneBuffers_->geometryFitsDescriptors(context);
    std::vector<std::string> defines = extraDefines;
    if (bound) defines.push_back("VKRT_BOUND_GEOMETRY");
    if (context.wideGeometryLoads()) defines.push_back("VKRT_WIDE_LOADS");
    if (data_.features.spheres) defines.push_back("VKRT_HAS_SPHERES");
    if (data_.features.shapes) defines.push_back("VKRT_HAS_SHAPES");
    if (data_.features.spheres && context.hasShaderFloat64()) defines.push_back("VKRT_SPHERE_FLOAT64");
    const CompiledShader shader = compileShader("raycast.comp", defines, shaderCacheDir);
    const auto bindings = sceneBuffers_->bindings(params_, bound);
    pipeline_ =
        std::make_unique<ComputePipeline>(context, shader.spirv, static_cast<uint32_t>(bindings.size()),
                                          static_cast<uint32_t>(sizeof(gpu::RaycastConstants)));
    pipeline_->bind(bindings);
    timer_ = std::make_unique<GpuTimer>(context);
}

GpuRaycaster::~GpuRaycaster() = default;

std::vector<gpu::GpuHit> GpuRaycaster::trace(const std::vector<gpu::GpuRay>& rays, RaycastMode mode,
                                             RaycastTiming* timing) {
    std::vector<gpu::GpuHit> hits(rays.size());
    if (rays.empty()) return hits;
    const GpuBuffer rayBuffer(context_, rays);
    const GpuBuffer hitBuffer(context_, rays.size() * sizeof(gpu::GpuHit));
    const gpu::RaycastConstants constants{rayBuffer.address(), hitBuffer.address(),
                                          static_cast<uint32_t>(rays.size()), static_cast<uint32_t>(mode)};
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = processCpuMs();
    context_.submitAndWait([&](VkCommandBuffer commands) {
        timer_->begin(commands);
        pipeline_->dispatch(commands, &constants, sizeof(constants),
                            (constants.count + VKRT_RAYCAST_WORKGROUP - 1) / VKRT_RAYCAST_WORKGROUP, 1);
        timer_->end(commands);
        makeShaderWritesVisibleToHost(commands);
    });
    if (timing) {
        timing->wallMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        timing->gpuMs = timer_->elapsedMs();
        timing->cpuMs = processCpuMs() - cpuStart;
    }
    hitBuffer.download(hits.data(), hits.size() * sizeof(gpu::GpuHit));
    return hits;
}

}  // namespace vkrt
