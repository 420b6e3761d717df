#include "gpu/workgroup_order.h"

#include <algorithm>
#include <cstdlib>
#include <thread>
#include <vector>

#include "spread_workgroups.h"

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

uint32_t widestThreadGap(uint32_t items, uint32_t spreadFor, uint32_t threads) {
    // Which thread takes each item (workgroups in launch order, column by column), then the items in order,
    // each thread's gap since its last.
    const SpreadGrid grid = spreadGrid(items, spreadFor);
    const uint32_t groups = grid.perColumn * grid.columns, run = groups / threads;
    std::vector<uint32_t> owner(items);
    for (uint32_t g = 0; g < groups; ++g) {
        const uint32_t item = shading::spreadItem(g % grid.perColumn, g / grid.perColumn, grid.columns);
        if (item < items)
            owner[item] = run > 0 && g < run * threads ? g / run : (g - run * threads) % threads;
    }
    std::vector<int64_t> last(threads, -1);
    int64_t widest = 0;
    for (uint32_t item = 0; item < items; ++item) {
        widest = std::max(widest, item - last[owner[item]]);
        last[owner[item]] = item;
    }
    for (const int64_t item : last) widest = std::max(widest, items - item);
    return static_cast<uint32_t>(widest);
}

}  // namespace vkrt
