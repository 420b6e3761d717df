#include "gpu/gpu_buffer.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "common/large_buffer.h"
#include "common/memory_need.h"
#include "gpu/vulkan_check.h"

namespace vkrt {

GpuBuffer::GpuBuffer(const VulkanContext& context, VkDeviceSize bytes) : context_(&context) {
    create(bytes, Placement::Device);
}

GpuBuffer::GpuBuffer(const VulkanContext& context, const void* data, VkDeviceSize bytes)
    : context_(&context) {
    create(bytes, Placement::Device);
    if (bytes > 0) upload(data, bytes);
}

GpuBuffer::GpuBuffer(const VulkanContext& context, VkDeviceSize bytes,
                     const std::function<void(void* mapped)>& write)
    : context_(&context) {
    create(bytes, Placement::Device);
    if (bytes > 0) writeWith(bytes, 0, write);
}

GpuBuffer::~GpuBuffer() {
    release();
}

GpuBuffer::GpuBuffer(GpuBuffer&& other) noexcept {
    *this = std::move(other);
}

GpuBuffer& GpuBuffer::operator=(GpuBuffer&& other) noexcept {
    if (this != &other) {
        release();
        context_ = std::exchange(other.context_, nullptr);
        buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        address_ = std::exchange(other.address_, 0);
        size_ = std::exchange(other.size_, 0);
        hostVisible_ = std::exchange(other.hostVisible_, false);
        hostCached_ = std::exchange(other.hostCached_, false);
    }
    return *this;
}

void GpuBuffer::release() {
    if (!context_) return;
    if (buffer_) vkDestroyBuffer(context_->device(), buffer_, nullptr);
    if (memory_) {
        vkFreeMemory(context_->device(), memory_, nullptr);
        context_->trackAllocation(-static_cast<int64_t>(size_));
    }
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

void GpuBuffer::create(VkDeviceSize bytes, Placement placement) {
    size_ = std::max<VkDeviceSize>(bytes, 16);
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size_;
    // Any buffer may be bound as storage or read as texels (ComputePipeline's BindingKind).
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                 VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                 VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(context_->device(), &info, nullptr, &buffer_));
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(context_->device(), buffer_, &requirements);

    // Device-local memory of the device's main heap, host-visible too where it can be (lavapipe, resizable
    // BAR) so that uploads map it, unless staged buffers were asked for (ContextOptions::deviceBuffers);
    // upload staging takes any host-visible memory, readback staging cached host memory first. (A small
    // device-local, host-visible heap beside the main one, as on GPUs without resizable BAR, is not used.)
    const VkMemoryPropertyFlags mappable =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    const VkMemoryPropertyFlags local = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    const uint32_t allowed = requirements.memoryTypeBits;
    int type = -1;
    switch (placement) {
        case Placement::Device:
            // Staged: memory the host does not map, which only the device's copies reach; where every
            // device-local type is mappable (lavapipe, a device sharing the host's memory), mapped all the
            // same.
            if (!context_->mapsDeviceBuffers()) {
                type = context_->findMemoryType(allowed, local, context_->deviceHeap(),
                                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
            }
            if (type < 0) type = context_->findMemoryType(allowed, local | mappable, context_->deviceHeap());
            if (type < 0) type = context_->findMemoryType(allowed, local, context_->deviceHeap());
            break;
        case Placement::Readback:
            type = context_->findMemoryType(allowed, mappable | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
            if (type < 0) type = context_->findMemoryType(allowed, mappable);
            break;
        case Placement::Upload:
            type = context_->findMemoryType(allowed, mappable);
            break;
    }
    if (type < 0) type = context_->findMemoryType(allowed, 0);
    if (type < 0) throw GpuError("no memory type for a storage buffer");
    const VkMemoryPropertyFlags properties = context_->memoryProperties().memoryTypes[type].propertyFlags;
    hostVisible_ = (properties & mappable) == mappable;
    hostCached_ = hostVisible_ && (properties & VK_MEMORY_PROPERTY_HOST_CACHED_BIT) != 0;

    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.pNext = &flags;
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = static_cast<uint32_t>(type);
    const VkResult result = vkAllocateMemory(context_->device(), &allocate, nullptr, &memory_);
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY) {
        throw GpuError("out of GPU memory allocating " + formatBytes(size_) + " (" +
                       formatBytes(context_->allocatedBytes()) + " held already)");
    }
    VK_CHECK(result);
    context_->trackAllocation(static_cast<int64_t>(size_));
    VK_CHECK(vkBindBufferMemory(context_->device(), buffer_, memory_, 0));
    VkBufferDeviceAddressInfo addressInfo{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    addressInfo.buffer = buffer_;
    address_ = vkGetBufferDeviceAddress(context_->device(), &addressInfo);
    // A CPU device's memory is the process's own, and first touching it 4 KiB at a time costs about 20 us a
    // page on a virtual machine (docs/performance-log.md): a large buffer asks for huge pages before it is
    // written. DamagedHelmet's render on lavapipe, 112 MB of texels written into fresh memory: 537 -> 294 ms.
    if (hostVisible_ && size_ >= kHugePageBytes &&
        context_->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        void* mapped = nullptr;  // a hint: a buffer that cannot be mapped here is left as it is
        if (vkMapMemory(context_->device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped) == VK_SUCCESS) {
            adviseHugePages(mapped, size_);
            vkUnmapMemory(context_->device(), memory_);
        }
    }
}

void GpuBuffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (bytes == 0) return;
    writeWith(bytes, offset, [&](void* mapped) { std::memcpy(mapped, data, bytes); });
}

void GpuBuffer::writeWith(VkDeviceSize bytes, VkDeviceSize offset,
                          const std::function<void(void* mapped)>& write) {
    if (hostVisible_) {
        void* mapped = nullptr;
        VK_CHECK(vkMapMemory(context_->device(), memory_, offset, bytes, 0, &mapped));
        write(mapped);
        vkUnmapMemory(context_->device(), memory_);
        return;
    }
    writeStaged(bytes, offset, write);
}

void GpuBuffer::writeStaged(VkDeviceSize bytes, VkDeviceSize offset,
                            const std::function<void(void* mapped)>& write) {
    GpuBuffer staging;
    staging.context_ = context_;
    staging.create(bytes, Placement::Upload);
    if (!staging.hostVisible_) throw GpuError("no host-visible memory to write a buffer through");
    staging.writeWith(bytes, 0, write);
    context_->submitAndWait([&](VkCommandBuffer commands) {
        const VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(commands, staging.buffer_, buffer_, 1, &region);
        // The copy's writes made visible to the kernels that read the buffer next.
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             0, 1, &barrier, 0, nullptr, 0, nullptr);
    });
}

void GpuBuffer::uploadStaged(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (bytes == 0) return;
    writeStaged(bytes, offset, [&](void* mapped) { std::memcpy(mapped, data, bytes); });
}

void GpuBuffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
    readWith(bytes, offset, [&](const void* mapped) { std::memcpy(data, mapped, bytes); });
}

void GpuBuffer::downloadStaged(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
    readStaged(bytes, offset, [&](const void* mapped) { std::memcpy(data, mapped, bytes); });
}

void GpuBuffer::readWith(VkDeviceSize bytes, VkDeviceSize offset,
                         const std::function<void(const void* mapped)>& read) const {
    if (bytes == 0) return;
    // A few words (the ray counters, read after every dispatch) are read in place even uncached: a copy on
    // the device and a wait for it would cost more than their few bus round trips.
    constexpr VkDeviceSize kUncachedReadBytes = 4 << 10;
    if (hostVisible_ && (hostCached_ || bytes <= kUncachedReadBytes)) {
        void* mapped = nullptr;
        VK_CHECK(vkMapMemory(context_->device(), memory_, offset, bytes, 0, &mapped));
        read(mapped);
        vkUnmapMemory(context_->device(), memory_);
        return;
    }
    readStaged(bytes, offset, read);
}

void GpuBuffer::readStaged(VkDeviceSize bytes, VkDeviceSize offset,
                           const std::function<void(const void* mapped)>& read) const {
    if (bytes == 0) return;
    GpuBuffer staging;
    staging.context_ = context_;
    staging.create(bytes, Placement::Readback);
    if (!staging.hostVisible_) throw GpuError("no host-visible memory to read a buffer back through");
    context_->submitAndWait([&](VkCommandBuffer commands) {
        const VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(commands, buffer_, staging.buffer_, 1, &region);
        // The copy's writes made visible to the host's reads of the mapped staging memory.
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                             &barrier, 0, nullptr, 0, nullptr);
    });
    void* mapped = nullptr;
    VK_CHECK(vkMapMemory(context_->device(), staging.memory_, 0, bytes, 0, &mapped));
    read(mapped);
    vkUnmapMemory(context_->device(), staging.memory_);
}

void GpuBuffer::fillZero(VkDeviceSize offset, VkDeviceSize bytes) {
    context_->submitAndWait(
        [&](VkCommandBuffer commands) { vkCmdFillBuffer(commands, buffer_, offset, bytes, 0); });
}

}  // namespace vkrt
