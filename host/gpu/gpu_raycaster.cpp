#include "gpu/gpu_raycaster.h"

#include <chrono>

#include "gpu/shader_compiler.h"
#include "gpu/vulkan_check.h"

namespace vkrt {

GpuRaycaster::GpuRaycaster(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                           const std::string& shaderCacheDir)
    : context_(context), data_(packScene(scene, bvh)) {
    sceneBuffers_ = std::make_unique<GpuSceneBuffers>(context, data_);
    gpu::SceneParams params{};
    params.counts = glm::uvec4(0, 0, data_.triangles.size(), 0);
    sceneBuffers_->fillAddresses(params);
    params_ = GpuBuffer(context, &params, sizeof(params));
    const bool bound = sceneBuffers_->geometryFitsDescriptors(context);
    const std::vector<std::string> defines =
        bound ? std::vector<std::string>{"VKRT_BOUND_GEOMETRY"} : std::vector<std::string>{};
    const CompiledShader shader = compileShader("raycast.comp", defines, shaderCacheDir);
    const auto bindings = sceneBuffers_->bindings(params_, bound);
    pipeline_ =
        std::make_unique<ComputePipeline>(context, shader.spirv, static_cast<uint32_t>(bindings.size()),
                                          static_cast<uint32_t>(sizeof(gpu::RaycastConstants)));
    pipeline_->bind(bindings);
    if (context.hasTimestamps()) {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2;
        VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &queries_));
    }
}

GpuRaycaster::~GpuRaycaster() {
    if (queries_) vkDestroyQueryPool(context_.device(), queries_, nullptr);
}

std::vector<gpu::GpuHit> GpuRaycaster::trace(const std::vector<gpu::GpuRay>& rays, RaycastMode mode,
                                             RaycastTiming* timing) {
    std::vector<gpu::GpuHit> hits(rays.size());
    if (rays.empty()) return hits;
    const GpuBuffer rayBuffer(context_, rays);
    const GpuBuffer hitBuffer(context_, rays.size() * sizeof(gpu::GpuHit));
    const gpu::RaycastConstants constants{rayBuffer.address(), hitBuffer.address(),
                                          static_cast<uint32_t>(rays.size()), static_cast<uint32_t>(mode)};
    const auto start = std::chrono::steady_clock::now();
    context_.submitAndWait([&](VkCommandBuffer commands) {
        if (queries_) {
            vkCmdResetQueryPool(commands, queries_, 0, 2);
            vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
        }
        pipeline_->dispatch(commands, &constants, sizeof(constants),
                            (constants.count + VKRT_RAYCAST_WORKGROUP - 1) / VKRT_RAYCAST_WORKGROUP, 1);
        if (queries_) vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
        VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        after.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        after.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &after, 0,
                             nullptr, 0, nullptr);
    });
    if (timing) {
        timing->wallMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        timing->gpuMs = 0.0;
        if (queries_) {
            uint64_t stamps[2] = {};
            VK_CHECK(vkGetQueryPoolResults(context_.device(), queries_, 0, 2, sizeof(stamps), stamps,
                                           sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
            timing->gpuMs = static_cast<double>(stamps[1] - stamps[0]) * context_.timestampPeriodNs() * 1e-6;
        }
    }
    hitBuffer.download(hits.data(), hits.size() * sizeof(gpu::GpuHit));
    for (gpu::GpuHit& hit : hits) {
        if (hit.triangle != VKRT_NO_HIT) hit.triangle = data_.sceneTriangle[hit.triangle];
    }
    return hits;
}

}  // namespace vkrt
