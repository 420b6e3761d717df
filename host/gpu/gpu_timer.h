// GPU time of a stretch of commands, from two timestamp queries. Without timestamp support on the queue
// it records nothing and reports 0.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/vulkan_context.h"

namespace vkrt {

class GpuTimer {
  public:
    explicit GpuTimer(const VulkanContext& context);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    void begin(VkCommandBuffer commands) const;
    void end(VkCommandBuffer commands) const;
    // Milliseconds between begin() and end(), once the commands have completed.
    double elapsedMs() const;

  private:
    const VulkanContext& context_;
    VkQueryPool queries_ = VK_NULL_HANDLE;
};

// A barrier after compute work whose results the host reads (mapped) or copies out (staged).
void makeShaderWritesVisibleToHost(VkCommandBuffer commands);

}  // namespace vkrt
