#include "gpu/vulkan_check.h"

#include <filesystem>

namespace vkrt {

const char* vkResultName(VkResult result) {
    switch (result) {
#define VKRT_RESULT_NAME(r) \
    case r:                 \
        return #r;
        VKRT_RESULT_NAME(VK_SUCCESS)
        VKRT_RESULT_NAME(VK_NOT_READY)
        VKRT_RESULT_NAME(VK_TIMEOUT)
        VKRT_RESULT_NAME(VK_INCOMPLETE)
        VKRT_RESULT_NAME(VK_ERROR_OUT_OF_HOST_MEMORY)
        VKRT_RESULT_NAME(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        VKRT_RESULT_NAME(VK_ERROR_INITIALIZATION_FAILED)
        VKRT_RESULT_NAME(VK_ERROR_DEVICE_LOST)
        VKRT_RESULT_NAME(VK_ERROR_MEMORY_MAP_FAILED)
        VKRT_RESULT_NAME(VK_ERROR_LAYER_NOT_PRESENT)
        VKRT_RESULT_NAME(VK_ERROR_EXTENSION_NOT_PRESENT)
        VKRT_RESULT_NAME(VK_ERROR_FEATURE_NOT_PRESENT)
        VKRT_RESULT_NAME(VK_ERROR_INCOMPATIBLE_DRIVER)
        VKRT_RESULT_NAME(VK_ERROR_TOO_MANY_OBJECTS)
        VKRT_RESULT_NAME(VK_ERROR_FORMAT_NOT_SUPPORTED)
        VKRT_RESULT_NAME(VK_ERROR_FRAGMENTED_POOL)
        VKRT_RESULT_NAME(VK_ERROR_OUT_OF_POOL_MEMORY)
        VKRT_RESULT_NAME(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        VKRT_RESULT_NAME(VK_ERROR_FRAGMENTATION)
        VKRT_RESULT_NAME(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        VKRT_RESULT_NAME(VK_ERROR_UNKNOWN)
#undef VKRT_RESULT_NAME
        default:
            return "unknown VkResult";
    }
}

void throwVkError(VkResult result, const char* call, const char* file, int line) {
    if (result == VK_ERROR_DEVICE_LOST) {
        throw DeviceLostError(std::string("the device was lost (") + call +
                              " returned VK_ERROR_DEVICE_LOST)");
    }
    throw GpuError(std::string(call) + " failed with " + vkResultName(result) + " (" +
                   std::filesystem::path(file).filename().string() + ":" + std::to_string(line) + ")");
}

}  // namespace vkrt
