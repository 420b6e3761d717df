// Which order a dispatch's workgroups take their work in (shaders/spread_workgroups.h): in columns, one for
// each thread of a CPU device (whose threads each take one contiguous run of workgroups), in order on GPUs.
#pragma once

#include <cstdint>
#include <string>

#include "gpu/vulkan_context.h"

namespace vkrt {

enum class WorkgroupOrder {
    Auto,     // by the device: Spread on a CPU device (lavapipe), InOrder on a GPU
    InOrder,  // workgroup g takes item g
    Spread,   // in columns, one for each of the host's threads (spreadThreads)
};

// `wanted`, or for Auto the device's order.
WorkgroupOrder workgroupOrderFor(WorkgroupOrder wanted, const VulkanContext& context);

// The threads a spread order makes columns for: lavapipe's, which are LP_NUM_THREADS when that is set, else
// one per online processor (as Mesa counts them); 1 in order. A count of threads that divides the columns
// (lavapipe's own limit below the processors) still gets items from the whole range.
uint32_t spreadThreads(WorkgroupOrder order);

// "in order", or "spread over N threads", for reports.
std::string workgroupOrderName(WorkgroupOrder order);

// The workgroups of a dispatch of `items` spread for `threads` threads: `columns` (at most one per item) of
// `perColumn` each; the dispatch is perColumn x columns with the columns its slowest dimension.
struct SpreadGrid {
    uint32_t perColumn = 0;
    uint32_t columns = 1;
};
SpreadGrid spreadGrid(uint32_t items, uint32_t threads);

}  // namespace vkrt
