#include "gpu/vulkan_context.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include "common/memory_need.h"
#include "gpu/vulkan_check.h"

namespace vkrt {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VkInstance createInstance(bool validation) {
    if (validation) {
        uint32_t count = 0;
        VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
        std::vector<VkLayerProperties> layers(count);
        VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
        const bool found = std::any_of(layers.begin(), layers.end(), [](const VkLayerProperties& l) {
            return std::strcmp(l.layerName, kValidationLayer) == 0;
        });
        if (!found) {
            throw GpuError(std::string(kValidationLayer) +
                           " was requested but is not installed "
                           "(Debian: vulkan-validationlayers)");
        }
    }
    VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    application.pApplicationName = "vkrt";
    application.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &application;
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    if (validation) {
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &kValidationLayer;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = extensions;
    }
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
        throw GpuError("no Vulkan driver found (for the CPU device, install Debian's mesa-vulkan-drivers)");
    }
    VK_CHECK(result);
    return instance;
}

const char* typeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "CPU";
        default:
            return "other";
    }
}

// Lower is preferred.
int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 3;
        default:
            return 4;
    }
}

int computeQueueFamily(VkPhysicalDevice device, uint32_t* timestampBits) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    for (uint32_t i = 0; i < count; ++i) {
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            if (timestampBits) *timestampBits = families[i].timestampValidBits;
            return static_cast<int>(i);
        }
    }
    return -1;
}

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
    uint32_t count = 0;
    if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr) != VK_SUCCESS) return false;
    std::vector<VkExtensionProperties> extensions(count);
    if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()) != VK_SUCCESS)
        return false;
    return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

DeviceDescription describe(VkPhysicalDevice device, int index) {
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    VkPhysicalDeviceProperties basic;
    vkGetPhysicalDeviceProperties(device, &basic);
    if (basic.apiVersion >= VK_API_VERSION_1_2) properties.pNext = &driver;
    vkGetPhysicalDeviceProperties2(device, &properties);

    DeviceDescription d;
    d.index = index;
    d.name = basic.deviceName;
    d.type = typeName(basic.deviceType);
    d.apiVersion = std::to_string(VK_API_VERSION_MAJOR(basic.apiVersion)) + "." +
                   std::to_string(VK_API_VERSION_MINOR(basic.apiVersion)) + "." +
                   std::to_string(VK_API_VERSION_PATCH(basic.apiVersion));
    if (basic.apiVersion < VK_API_VERSION_1_2) {
        d.unusableBecause = "Vulkan 1.2 is required";
        return d;
    }
    d.driver = std::string(driver.driverName) + " " + driver.driverInfo;
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(device, &memory);
    for (uint32_t h = 0; h < memory.memoryHeapCount; ++h) {
        std::string line = "heap " + std::to_string(h) + ": " + formatBytes(memory.memoryHeaps[h].size);
        if (memory.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) line += ", device-local";
        std::string types;
        for (uint32_t t = 0; t < memory.memoryTypeCount; ++t) {
            if (memory.memoryTypes[t].heapIndex != h) continue;
            const VkMemoryPropertyFlags f = memory.memoryTypes[t].propertyFlags;
            std::string type;
            for (const auto& [bit, name] : {std::pair{VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "device-local"},
                                            std::pair{VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, "host-visible"},
                                            std::pair{VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "host-coherent"},
                                            std::pair{VK_MEMORY_PROPERTY_HOST_CACHED_BIT, "host-cached"}}) {
                if (!(f & bit)) continue;
                if (!type.empty()) type += ' ';
                type += name;
            }
            if (!types.empty()) types += " | ";
            types += std::to_string(t);
            types += ' ';
            types += type.empty() ? "(none)" : type;
        }
        d.memoryHeaps.push_back(line + "; types: " + (types.empty() ? "none" : types));
    }
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);
    if (!features12.bufferDeviceAddress)
        d.unusableBecause = "bufferDeviceAddress is not supported";
    else if (computeQueueFamily(device, nullptr) < 0)
        d.unusableBecause = "no compute queue";
    else
        d.usable = true;
    return d;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

}  // namespace

std::vector<DeviceDescription> listDevices() {
    VkInstance instance = createInstance(false);
    std::vector<DeviceDescription> result;
    try {
        const auto devices = physicalDevices(instance);
        for (size_t i = 0; i < devices.size(); ++i)
            result.push_back(describe(devices[i], static_cast<int>(i)));
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return result;
}

VulkanContext::VulkanContext(const ContextOptions& options) {
    instance_ = createInstance(options.validation);
    try {
        if (options.validation) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            if (!create) throw GpuError("vkCreateDebugUtilsMessengerEXT is unavailable");
            VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            info.pfnUserCallback = &VulkanContext::onValidationMessage;
            info.pUserData = this;
            VK_CHECK(create(instance_, &info, nullptr, &messenger_));
        }

        // Choose the device.
        const auto devices = physicalDevices(instance_);
        if (devices.empty())
            throw GpuError("Vulkan reports no devices (for the CPU device, install mesa-vulkan-drivers)");
        int chosen = -1;
        if (options.deviceIndex >= 0) {
            if (options.deviceIndex >= static_cast<int>(devices.size())) {
                throw NoSuchDeviceError("--device-index " + std::to_string(options.deviceIndex) +
                                        ": Vulkan reports only " + std::to_string(devices.size()) +
                                        " device(s) (see vkrt --list-devices)");
            }
            const DeviceDescription d = describe(devices[options.deviceIndex], options.deviceIndex);
            if (!d.usable)
                throw GpuError("device " + std::to_string(d.index) + " (" + d.name +
                               "): " + d.unusableBecause);
            chosen = options.deviceIndex;
        } else {
            // The usable devices of the preferred type, in Vulkan's order; localRank picks among them.
            int bestRank = 1 << 30;
            std::vector<int> preferred;
            for (size_t i = 0; i < devices.size(); ++i) {
                if (!describe(devices[i], static_cast<int>(i)).usable) continue;
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devices[i], &p);
                if (typeRank(p.deviceType) < bestRank) {
                    bestRank = typeRank(p.deviceType);
                    preferred.clear();
                }
                if (typeRank(p.deviceType) == bestRank) preferred.push_back(static_cast<int>(i));
            }
            if (preferred.empty())
                throw GpuError("no Vulkan device supports what vkrt needs (see --list-devices)");
            chosen = preferred[static_cast<size_t>(std::max(options.localRank, 0)) % preferred.size()];
        }
        physicalDevice_ = devices[chosen];
        description_ = describe(physicalDevice_, chosen);
        vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
        vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
        for (uint32_t i = 0; i < memoryProperties_.memoryHeapCount; ++i) {
            const VkMemoryHeap& heap = memoryProperties_.memoryHeaps[i];
            if ((heap.flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
                (deviceHeap_ < 0 || heap.size > memoryProperties_.memoryHeaps[deviceHeap_].size)) {
                deviceHeap_ = static_cast<int>(i);
            }
        }
        if (deviceHeap_ < 0) deviceHeap_ = 0;
        mapsDeviceBuffers_ = options.deviceBuffers == DeviceBuffers::Mapped;
        VkPhysicalDeviceVulkan11Properties properties11{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
        VkPhysicalDeviceVulkan12Properties properties12{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES};
        properties11.pNext = &properties12;
        VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        properties2.pNext = &properties11;
        vkGetPhysicalDeviceProperties2(physicalDevice_, &properties2);
        maxAllocationBytes_ = properties11.maxMemoryAllocationSize;
        ieeeFloats_ = properties12.shaderSignedZeroInfNanPreserveFloat32 == VK_TRUE;
        const VkSubgroupFeatureFlags subgroupSums =
            VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
        subgroupArithmetic_ = (properties11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
                              (properties11.subgroupSupportedOperations & subgroupSums) == subgroupSums;
        const VkSubgroupFeatureFlags subgroupVotes =
            VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT;
        subgroupVote_ = (properties11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
                        (properties11.subgroupSupportedOperations & subgroupVotes) == subgroupVotes;
        memoryBudget_ = hasDeviceExtension(physicalDevice_, VK_EXT_MEMORY_BUDGET_EXTENSION_NAME);
        queueFamily_ = static_cast<uint32_t>(computeQueueFamily(physicalDevice_, &timestampValidBits_));

        // The logical device: one compute queue, buffer device addresses.
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = queueFamily_;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        VkPhysicalDeviceFeatures supported{};
        vkGetPhysicalDeviceFeatures(physicalDevice_, &supported);
        shaderFloat64_ = supported.shaderFloat64 == VK_TRUE;
        VkPhysicalDeviceFeatures enabled{};
        enabled.shaderFloat64 =
            supported.shaderFloat64;  // for spheres far larger than the view (sphere_geometry.h)
        VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        features12.bufferDeviceAddress = VK_TRUE;
        VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        deviceInfo.pNext = &features12;
        deviceInfo.pEnabledFeatures = &enabled;
        deviceInfo.queueCreateInfoCount = 1;
        deviceInfo.pQueueCreateInfos = &queueInfo;
        const char* budgetExtension = VK_EXT_MEMORY_BUDGET_EXTENSION_NAME;
        if (memoryBudget_) {
            deviceInfo.enabledExtensionCount = 1;
            deviceInfo.ppEnabledExtensionNames = &budgetExtension;
        }
        VK_CHECK(vkCreateDevice(physicalDevice_, &deviceInfo, nullptr, &device_));
        vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        poolInfo.queueFamilyIndex = queueFamily_;
        VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VK_CHECK(vkCreateFence(device_, &fenceInfo, nullptr, &fence_));
    } catch (...) {
        release();
        throw;
    }
}

VulkanContext::~VulkanContext() {
    release();
}

void VulkanContext::release() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (commandPool_) vkDestroyCommandPool(device_, commandPool_, nullptr);
        vkDestroyDevice(device_, nullptr);
        device_ = VK_NULL_HANDLE;
    }
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
        messenger_ = VK_NULL_HANDLE;
    }
    if (instance_) {
        vkDestroyInstance(instance_, nullptr);
        instance_ = VK_NULL_HANDLE;
    }
}

VkBool32 VulkanContext::onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                            VkDebugUtilsMessageTypeFlagsEXT,
                                            const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
    static_cast<VulkanContext*>(self)->validationMessages_++;
    std::fprintf(stderr, "vkrt: validation: %s\n", data && data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

void VulkanContext::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const {
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocate.commandPool = commandPool_;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = 1;
    VkCommandBuffer commands = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(device_, &allocate, &commands));
    try {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(commands, &begin));
        record(commands);
        VK_CHECK(vkEndCommandBuffer(commands));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &commands;
        VK_CHECK(vkResetFences(device_, 1, &fence_));
        VK_CHECK(vkQueueSubmit(queue_, 1, &submit, fence_));
        VK_CHECK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
    } catch (...) {
        vkFreeCommandBuffers(device_, commandPool_, 1, &commands);
        throw;
    }
    vkFreeCommandBuffers(device_, commandPool_, 1, &commands);
}

DeviceMemoryBudget VulkanContext::memoryBudget() const {
    DeviceMemoryBudget budget;
    budget.heapBytes = memoryProperties_.memoryHeaps[deviceHeap_].size;
    budget.bytes = budget.heapBytes;
    budget.source = "memory heap";
    if (memoryBudget_) {
        // What this process may still take: the budget (which counts other processes' use) less what the
        // driver says this process holds already.
        VkPhysicalDeviceMemoryBudgetPropertiesEXT reported{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_BUDGET_PROPERTIES_EXT};
        VkPhysicalDeviceMemoryProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_PROPERTIES_2};
        properties.pNext = &reported;
        vkGetPhysicalDeviceMemoryProperties2(physicalDevice_, &properties);
        const VkDeviceSize available = reported.heapBudget[deviceHeap_];
        const VkDeviceSize used = reported.heapUsage[deviceHeap_];
        if (available > 0) {
            budget.bytes = available > used ? available - used : 0;
            budget.source = "memory budget (VK_EXT_memory_budget)";
        }
    }
    return budget;
}

void VulkanContext::trackAllocation(int64_t bytes) const {
    const uint64_t now =
        allocatedBytes_.fetch_add(static_cast<uint64_t>(bytes)) + static_cast<uint64_t>(bytes);
    uint64_t peak = peakAllocatedBytes_.load();
    while (now > peak && !peakAllocatedBytes_.compare_exchange_weak(peak, now)) {
    }
}

int VulkanContext::findMemoryType(uint32_t allowedTypes, VkMemoryPropertyFlags required, int heap,
                                  VkMemoryPropertyFlags excluded) const {
    for (uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
        const VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[i].propertyFlags;
        if ((allowedTypes & (1u << i)) &&
            (heap < 0 || memoryProperties_.memoryTypes[i].heapIndex == static_cast<uint32_t>(heap)) &&
            (flags & required) == required && (flags & excluded) == 0) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

}  // namespace vkrt
