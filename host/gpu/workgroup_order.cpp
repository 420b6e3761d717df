#include "gpu/workgroup_order.h"

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace vkrt {

WorkgroupOrder workgroupOrderFor(WorkgroupOrder wanted, const VulkanContext& context) {
    if (wanted != WorkgroupOrder::Auto) return wanted;
    return context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ? WorkgroupOrder::Spread
                                                                          : WorkgroupOrder::InOrder;
}

uint32_t spreadThreads(WorkgroupOrder order) {
    if (order != WorkgroupOrder::Spread) return 1;
    if (const char* set = std::getenv("LP_NUM_THREADS")) {
        const long threads = std::strtol(set, nullptr, 10);
        if (threads > 0) return static_cast<uint32_t>(std::min(threads, 1024L));
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

std::string workgroupOrderName(WorkgroupOrder order) {
    if (order != WorkgroupOrder::Spread) return "in order";
    return "spread over " + std::to_string(spreadThreads(order)) + " threads";
}

SpreadGrid spreadGrid(uint32_t items, uint32_t threads) {
    SpreadGrid grid;
    grid.columns = std::max(1u, std::min(threads, items));
    grid.perColumn = (items + grid.columns - 1) / grid.columns;
    return grid;
}

}  // namespace vkrt
