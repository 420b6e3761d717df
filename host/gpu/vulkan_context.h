// The Vulkan instance, the chosen device, its compute queue and a command pool. Device choice: discrete
// GPU first, then integrated, virtual and CPU (lavapipe), or the one `deviceIndex` names.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace vkrt {

// Where vkrt's device buffers lie (gpu_buffer.h): in device-local memory the host maps where the device has
// such (a CPU device's own memory, a GPU's through resizable BAR), written in place; or in device-local
// memory the host does not see, written and read through staging copies that the device makes. On an H200
// both traced alike, and staging took the scene's buffers 2 to 7 times as long to write
// (docs/performance-log.md): mapped is the default; staged is there to measure (ray_benchmark
// --device-buffers).
enum class DeviceBuffers { Mapped, Staged };

struct ContextOptions {
    bool validation = false;  // enable VK_LAYER_KHRONOS_validation and count its messages
    DeviceBuffers deviceBuffers = DeviceBuffers::Mapped;
    int deviceIndex = -1;     // -1: choose automatically
    // Automatic choice among several devices of the preferred type: number localRank modulo their count (the
    // node-local rank of an MPI job, so that ranks on one machine take different GPUs).
    int localRank = 0;
};

struct DeviceDescription {
    int index = 0;
    std::string name;
    std::string type;    // "discrete GPU", "integrated GPU", "CPU", ...
    std::string driver;  // driver name and version string
    std::string apiVersion;
    bool usable = false;
    std::string unusableBecause;
    // Each memory heap: its size, whether it is device-local, and its memory types' properties
    // ("device-local host-visible host-coherent", ...), for --list-devices.
    std::vector<std::string> memoryHeaps;
};

// The device memory a render may take.
struct DeviceMemoryBudget {
    uint64_t bytes = 0;      // available to vkrt now
    uint64_t heapBytes = 0;  // the size of the heap it comes from
    std::string source;      // where `bytes` comes from: "memory heap", "memory budget (VK_EXT_memory_budget)"
};

// Every physical device Vulkan reports, with whether vkrt can use it.
std::vector<DeviceDescription> listDevices();

class VulkanContext {
  public:
    explicit VulkanContext(const ContextOptions& options = {});
    ~VulkanContext();
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    VkDevice device() const { return device_; }
    VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
    VkQueue queue() const { return queue_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memoryProperties_; }
    const DeviceDescription& description() const { return description_; }
    bool hasTimestamps() const { return timestampValidBits_ > 0; }
    // Whether shaders may use double precision (enabled when the device has it).
    bool hasShaderFloat64() const { return shaderFloat64_; }
    // Whether a shader can ask for IEEE 754's signed zeros, infinities and NaNs in single precision
    // (shaderSignedZeroInfNanPreserveFloat32; shaders/ieee_floats.glsl).
    bool keepsIeeeFloats() const { return ieeeFloats_; }
    // Whether compute shaders may sum across a subgroup (subgroupAdd, subgroupElect): kernels then add their
    // ray counts with one atomic per subgroup (VKRT_SUBGROUP_COUNTERS, shaders/trace.comp).
    bool hasSubgroupArithmetic() const { return subgroupArithmetic_; }
    // Whether compute shaders may vote across a subgroup (subgroupAll): both kernels on lavapipe chain the
    // samples of a SIMD group whose rays all escape (VKRT_CHAINS_ESCAPES, shaders/trace.comp).
    bool hasSubgroupVote() const { return subgroupVote_; }
    double timestampPeriodNs() const { return properties_.limits.timestampPeriod; }

    // Validation-layer warnings and errors seen so far (0 when validation is off).
    uint32_t validationMessages() const { return validationMessages_.load(); }

    // Records commands into a one-time command buffer, submits it and waits for it to finish.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

    // A memory type index with all of `required` and none of `excluded` among `allowedTypes` (and in `heap`,
    // when >= 0), or -1.
    int findMemoryType(uint32_t allowedTypes, VkMemoryPropertyFlags required, int heap = -1,
                       VkMemoryPropertyFlags excluded = 0) const;
    // Whether device buffers go in memory the host maps, where there is such (ContextOptions::deviceBuffers).
    bool mapsDeviceBuffers() const { return mapsDeviceBuffers_; }
    // The largest device-local heap, where vkrt's buffers go.
    int deviceHeap() const { return deviceHeap_; }
    // What the device heap offers now: with VK_EXT_memory_budget, its budget less this process's use;
    // otherwise the heap's size.
    DeviceMemoryBudget memoryBudget() const;
    // The largest single allocation the device allows (maxMemoryAllocationSize).
    uint64_t maxAllocationBytes() const { return maxAllocationBytes_; }

    // Device memory that vkrt's buffers hold now, and the most they held at once.
    void trackAllocation(int64_t bytes) const;
    uint64_t allocatedBytes() const { return allocatedBytes_.load(); }
    uint64_t peakAllocatedBytes() const { return peakAllocatedBytes_.load(); }

  private:
    void release();
    static VkBool32 VKAPI_PTR onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT types,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* self);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    uint32_t timestampValidBits_ = 0;
    bool shaderFloat64_ = false;
    bool ieeeFloats_ = false;
    bool mapsDeviceBuffers_ = true;
    bool subgroupArithmetic_ = false;
    bool subgroupVote_ = false;
    bool memoryBudget_ = false;  // VK_EXT_memory_budget is there (and enabled)
    int deviceHeap_ = -1;
    uint64_t maxAllocationBytes_ = 0;
    VkCommandPool commandPool_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memoryProperties_{};
    DeviceDescription description_;
    std::atomic<uint32_t> validationMessages_{0};
    mutable std::atomic<uint64_t> allocatedBytes_{0};
    mutable std::atomic<uint64_t> peakAllocatedBytes_{0};
};

}  // namespace vkrt
