#include "gpu/gpu_raycaster.h"

#include <algorithm>
#include <chrono>
#include <utility>

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
                           const std::string& shaderCacheDir, const std::vector<std::string>& extraDefines,
                           WorkgroupOrder order)
    : context_(context),
      data_(packScene(scene, bvh)),
      shaderCacheDir_(shaderCacheDir),
      defines_(extraDefines),
      order_(workgroupOrderFor(order, context)) {
    // A scene-access define among the caller's is a request for that way of reading the scene.
    SceneAccess wanted = SceneAccess::Auto;
    for (const auto& [define, access] : {std::pair{"VKRT_TEXEL_SCENE", SceneAccess::Texels},
                                         std::pair{"VKRT_BOUND_GEOMETRY", SceneAccess::Storage},
                                         std::pair{"VKRT_ADDRESSED_SCENE", SceneAccess::Addresses}}) {
        const auto found = std::find(defines_.begin(), defines_.end(), define);
        if (found == defines_.end()) continue;
        wanted = access;
        defines_.erase(found);
    }
    sceneAccess_ = chooseSceneAccess(context, data_, wanted);
    sceneBuffers_ = std::make_unique<GpuSceneBuffers>(context, data_, scene);
    gpu::SceneParams params{};
    params.primitiveCount = static_cast<uint32_t>(data_.primitives.size());
    sceneBuffers_->fillAddresses(params);
    params_ = GpuBuffer(context, &params, sizeof(params));
    for (const std::string& define : GpuSceneBuffers::accessDefines(sceneAccess_)) defines_.push_back(define);
    if (data_.features.spheres) defines_.push_back("VKRT_HAS_SPHERES");
    if (data_.features.shapes) defines_.push_back("VKRT_HAS_SHAPES");
    if (data_.features.csg) defines_.push_back("VKRT_HAS_CSG");  // else every solid is one shape
    for (const std::string& define : data_.features.solidShapesDefine()) defines_.push_back(define);
    if (data_.features.largeSpheres && context.hasShaderFloat64()) defines_.push_back("VKRT_SPHERE_FLOAT64");
    if (context.keepsIeeeFloats()) defines_.push_back("VKRT_IEEE_FLOATS");
    bindings_ = sceneBuffers_->bindings(params_, sceneAccess_);
    timer_ = std::make_unique<GpuTimer>(context);
}

GpuRaycaster::~GpuRaycaster() = default;

ComputePipeline& GpuRaycaster::pipelineFor(RaycastMode mode) {
    std::unique_ptr<ComputePipeline>& pipeline = pipelines_[mode == RaycastMode::Any ? 1 : 0];
    if (!pipeline) {
        std::vector<std::string> defines = defines_;
        if (mode == RaycastMode::Any) defines.push_back("VKRT_RAYCAST_ANY_HIT");
        const CompiledShader shader = compileShader("raycast.comp", defines, shaderCacheDir_);
        pipeline = std::make_unique<ComputePipeline>(context_, shader.spirv,
                                                     GpuSceneBuffers::bindingKinds(sceneAccess_),
                                                     static_cast<uint32_t>(sizeof(gpu::RaycastConstants)));
        pipeline->bind(bindings_);
    }
    return *pipeline;
}

std::vector<gpu::GpuHit> GpuRaycaster::trace(const std::vector<gpu::GpuRay>& rays, RaycastMode mode,
                                             RaycastTiming* timing, uint32_t repeats) {
    repeats = std::max(repeats, 1u);
    std::vector<gpu::GpuHit> hits(rays.size());
    if (rays.empty()) return hits;
    const GpuBuffer rayBuffer(context_, rays);
    const GpuBuffer hitBuffer(context_, rays.size() * sizeof(gpu::GpuHit));
    // One dispatch, of at most 65,535 workgroups (every device's least limit).
    const size_t blockCount = (rays.size() + VKRT_RAYCAST_WORKGROUP - 1) / VKRT_RAYCAST_WORKGROUP;
    if (blockCount > 65535u) {
        throw GpuError(std::to_string(rays.size()) + " rays are more than one dispatch holds (" +
                       std::to_string(65535u * VKRT_RAYCAST_WORKGROUP) + ")");
    }
    const SpreadGrid blocks = spreadGrid(static_cast<uint32_t>(blockCount), spreadThreads(order_));
    ComputePipeline& pipeline = pipelineFor(mode);
    const gpu::RaycastConstants constants{rayBuffer.address(), hitBuffer.address(),
                                          static_cast<uint32_t>(rays.size())};
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = processCpuMs();
    context_.submitAndWait([&](VkCommandBuffer commands) {
        timer_->begin(commands);
        for (uint32_t repeat = 0; repeat < repeats; ++repeat) {
            if (repeat > 0) {
                // The dispatches write the same hits: each after the one before.
                VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
                barrier.dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
                vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0, nullptr, 0,
                                     nullptr);
            }
            pipeline.dispatch(commands, &constants, sizeof(constants), blocks.perColumn, blocks.columns);
        }
        timer_->end(commands);
        makeShaderWritesVisibleToHost(commands);
    });
    if (timing) {
        timing->wallMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() /
            repeats;
        timing->gpuMs = timer_->elapsedMs() / repeats;
        timing->cpuMs = (processCpuMs() - cpuStart) / repeats;
    }
    hitBuffer.download(hits.data(), hits.size() * sizeof(gpu::GpuHit));
    return hits;
}

}  // namespace vkrt
