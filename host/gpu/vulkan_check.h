// Checking every VkResult: a failure throws GpuError naming the call, the result and the place. The check
// stays on in release builds (zeux/niagara's VK_CHECK_FORCE).
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace vkrt {

class GpuError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The device stopped working (VK_ERROR_DEVICE_LOST: a driver reset, a watchdog, a GPU fault). Nothing on it
// can be read back; what the host copied before is all that is left.
class DeviceLostError : public GpuError {
  public:
    using GpuError::GpuError;
};

// A device asked for that is not there (--device-index beyond the devices Vulkan reports): bad input, exit 2.
class NoSuchDeviceError : public GpuError {
  public:
    using GpuError::GpuError;
};

const char* vkResultName(VkResult result);

[[noreturn]] void throwVkError(VkResult result, const char* call, const char* file, int line);

}  // namespace vkrt

#define VK_CHECK(call)                                                       \
    do {                                                                     \
        const VkResult vkCheckResult_ = (call);                              \
        if (vkCheckResult_ != VK_SUCCESS) {                                  \
            ::vkrt::throwVkError(vkCheckResult_, #call, __FILE__, __LINE__); \
        }                                                                    \
    } while (0)
