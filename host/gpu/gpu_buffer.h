// A storage buffer with its own device memory and a buffer device address. Uploads map the memory when the
// device lets the host see it (lavapipe, resizable BAR) and go through a staging buffer otherwise (or when
// staged buffers were asked for: VulkanContext::mapsDeviceBuffers); downloads
// map it only where the host reads it through its caches (a CPU device's memory) or read a few bytes, and
// otherwise copy through a staging buffer in cached host memory: a discrete GPU's memory mapped over the bus
// is write-combined and uncached, and the host reads it a few bytes per bus round trip.
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
    // The staging path of `upload`, whatever the memory: the bytes written into host memory, then copied on
    // the device. Public so that devices whose memory is all mapped (lavapipe) test it.
    void uploadStaged(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
    // The staging path of `download`, whatever the memory: a copy on the device into host memory, cached
    // where the device has such, then read. Public so that devices whose memory is all cached test it.
    void downloadStaged(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
    // Has `read` take `bytes` from `offset` where the host can read them: the buffer's own mapped memory
    // where it is cached (or the bytes are a few words), else a staging buffer's. No copy of them in host
    // memory.
    void readWith(VkDeviceSize bytes, VkDeviceSize offset,
                  const std::function<void(const void* mapped)>& read) const;
    // Zeroes `bytes` from `offset` (a multiple of 4), or the whole buffer.
    void fillZero(VkDeviceSize offset = 0, VkDeviceSize bytes = VK_WHOLE_SIZE);

  private:
    // Where a buffer's memory lies: device-local (mapped where the host can see it), host memory the host
    // writes (upload staging), or host memory the host reads, cached where the device offers it (readback).
    enum class Placement { Device, Upload, Readback };

    void release();
    void create(VkDeviceSize bytes, Placement placement);
    // Has `write` fill `bytes` from `offset`, mapped or through a staging buffer.
    void writeWith(VkDeviceSize bytes, VkDeviceSize offset, const std::function<void(void* mapped)>& write);
    void writeStaged(VkDeviceSize bytes, VkDeviceSize offset, const std::function<void(void* mapped)>& write);
    void readStaged(VkDeviceSize bytes, VkDeviceSize offset,
                    const std::function<void(const void* mapped)>& read) const;

    const VulkanContext* context_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceAddress address_ = 0;
    VkDeviceSize size_ = 0;
    bool hostVisible_ = false;
    bool hostCached_ = false;
};

}  // namespace vkrt
