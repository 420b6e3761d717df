#include "gpu/device_memory_plan.h"

#include <algorithm>

namespace vkrt {

DeviceMemoryPlan planDeviceMemory(const VulkanContext& context, const MemoryNeed& scene, uint32_t width,
                                  uint32_t height, uint64_t limitBytes) {
    const DeviceMemoryBudget budget = context.memoryBudget();
    const std::string device = context.description().name;
    DeviceMemoryPlan plan;
    plan.budgetBytes = budget.bytes;
    plan.budgetSource = device + "'s " + budget.source;
    if (limitBytes > 0 && limitBytes < plan.budgetBytes) {
        plan.budgetBytes = limitBytes;
        plan.budgetSource = "--max-device-memory";
    }

    const uint64_t maxAllocation =
        context.maxAllocationBytes() > 0 ? context.maxAllocationBytes() : UINT64_MAX;
    if (const MemoryNeed::Part largest = scene.largest(); largest.bytes > maxAllocation) {
        throw MemoryError("the scene's " + largest.what + " need " + formatBytes(largest.bytes) +
                          " in one buffer, and " + device + " allows at most " + formatBytes(maxAllocation) +
                          " in one allocation");
    }
    // The image: as many rows as fit beside the scene, in one allocation.
    const uint64_t rowBytes = kAccumulationBytesPerPixel * width;
    const uint64_t free = plan.budgetBytes > scene.total() ? plan.budgetBytes - scene.total() : 0;
    const uint64_t rows = std::min<uint64_t>({height, free / rowBytes, maxAllocation / rowBytes});
    if (rows == 0) {
        throw MemoryError("the render needs more device memory than it has: the scene " + scene.describe() +
                          " and at least " + formatBytes(rowBytes) + " for one row of the image, against " +
                          formatBytes(plan.budgetBytes) + " (" + plan.budgetSource + ")");
    }
    // Bands of equal height, the last perhaps shorter.
    plan.tiles = static_cast<uint32_t>((height + rows - 1) / rows);
    plan.tileRows = (height + plan.tiles - 1) / plan.tiles;
    plan.need = scene;
    plan.need.add(plan.tiles > 1 ? "image accumulation (one tile)" : "image accumulation",
                  plan.tileRows * rowBytes);
    return plan;
}

}  // namespace vkrt
