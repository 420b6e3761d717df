// How a GPU render fits the device's memory, decided before anything is allocated: the scene's buffers must
// fit whole; the image's accumulation buffer is split into bands of rows (tiles) when it does not fit beside
// them, each band accumulated on the device and added up on the host.
#pragma once

#include <cstdint>
#include <string>

#include "common/memory_need.h"
#include "gpu/vulkan_context.h"

namespace vkrt {

struct DeviceMemoryPlan {
    MemoryNeed need;           // what the render will hold on the device: scene buffers and one tile
    uint64_t budgetBytes = 0;  // what it may hold
    std::string budgetSource;  // where that figure came from
    uint32_t tileRows = 0;     // image rows accumulated on the device at once
    uint32_t tiles = 0;        // bands of tileRows rows that cover the image
};

// Bytes of device accumulation per pixel: a running sum and its compensation, four floats each.
constexpr uint64_t kAccumulationBytesPerPixel = 32;

// Plans a width x height render of a scene whose buffers need `scene`, within what the device offers now
// (or `limitBytes`, when smaller and > 0). Throws MemoryError, with the figures, when the scene's buffers
// and one row of the image do not fit, or when one buffer is larger than the device allows in one allocation.
DeviceMemoryPlan planDeviceMemory(const VulkanContext& context, const MemoryNeed& scene, uint32_t width,
                                  uint32_t height, uint64_t limitBytes = 0);

}  // namespace vkrt
