// A storage buffer with its own device memory and a buffer device address. Uploads and downloads map the
// memory when the device lets the host see it (lavapipe, resizable BAR) and go through a staging buffer
// otherwise.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/vulkan_context.h"

namespace vkrt {

class GpuBuffer {
  public:
    GpuBuffer() = default;
    // A buffer of `bytes` (at least 16) in device-local memory where possible.
    GpuBuffer(const VulkanContext& context, VkDeviceSize bytes);
    // A buffer holding a copy of `data`.
    GpuBuffer(const VulkanContext& context, const void* data, VkDeviceSize bytes);
    template <typename T>
    GpuBuffer(const VulkanContext& context, const std::vector<T>& values)
        : GpuBuffer(context, values.data(), values.size() * sizeof(T)) {}
    // A buffer of `bytes` whose contents `write` puts straight into its mapped memory (a staging buffer's
    // where the host cannot see the device's): no copy of them in host memory first.
    GpuBuffer(const VulkanContext& context, VkDeviceSize bytes,
              const std::function<void(void* mapped)>& write);
    ~GpuBuffer();
    GpuBuffer(GpuBuffer&& other) noexcept;
    GpuBuffer& operator=(GpuBuffer&& other) noexcept;
    GpuBuffer(const GpuBuffer&) = delete;
    GpuBuffer& operator=(const GpuBuffer&) = delete;

    VkBuffer handle() const { return buffer_; }
    VkDeviceAddress address() const { return address_; }
    VkDeviceSize size() const { return size_; }
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

    void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
    // Zeroes `bytes` from `offset` (a multiple of 4), or the whole buffer.
    void fillZero(VkDeviceSize offset = 0, VkDeviceSize bytes = VK_WHOLE_SIZE);

  private:
    void release();
    void create(VkDeviceSize bytes, bool preferHostVisible);
    // Has `write` fill `bytes` from `offset`, mapped or through a staging buffer.
    void writeWith(VkDeviceSize bytes, VkDeviceSize offset, const std::function<void(void* mapped)>& write);

    const VulkanContext* context_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceAddress address_ = 0;
    VkDeviceSize size_ = 0;
    bool hostVisible_ = false;
};

}  // namespace vkrt
