#include "gpu/gpu_timer.h"

#include "gpu/vulkan_check.h"

namespace vkrt {

GpuTimer::GpuTimer(const VulkanContext& context) : context_(context) {
    if (!context.hasTimestamps()) return;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &queries_));
}

GpuTimer::~GpuTimer() {
    if (queries_) vkDestroyQueryPool(context_.device(), queries_, nullptr);
}

void GpuTimer::begin(VkCommandBuffer commands) const {
    if (!queries_) return;
    vkCmdResetQueryPool(commands, queries_, 0, 2);
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
}

void GpuTimer::end(VkCommandBuffer commands) const {
    if (queries_) vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
}

double GpuTimer::elapsedMs() const {
    if (!queries_) return 0.0;
    uint64_t stamps[2] = {};
    VK_CHECK(vkGetQueryPoolResults(context_.device(), queries_, 0, 2, sizeof(stamps), stamps,
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    return static_cast<double>(stamps[1] - stamps[0]) * context_.timestampPeriodNs() * 1e-6;
}

void makeShaderWritesVisibleToHost(VkCommandBuffer commands) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
}

}  // namespace vkrt
