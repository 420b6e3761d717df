// Binned SAH builder (Wald, "On fast construction of SAH-based bounding volume hierarchies", 2007).
// The top of the tree is split with every thread binning and partitioning blocks of each node's
// primitives; the subtrees below are built one per thread (sah_subtree_builder.h). Near the depth limit it
// falls back to median splits, so the depth bound holds for any input, 100k identical triangles included.
//
// The tree is the same on every run and for every thread count, node for node.
#pragma once

#include <cstdint>
#include <span>

#include "bvh/bvh.h"

namespace vkrt {

// How the build is divided into parallel work. The tree's nodes, bounds, leaves and primIndices do not
// depend on it, only the order in which nodes are numbered does (tests vary it to check that).
struct BinnedSahSchedule {
    // Nodes over more primitives than this are split by all threads together, block by block; nodes with
    // this many or fewer are the roots of subtrees, each built whole by one thread.
    uint32_t subtreeSize = 32 * 1024;
    uint32_t blockSize = 16 * 1024;  // primitives per block of parallel work
};

struct BinnedSahBuilder {
    static Bvh build(std::span<const Aabb> bounds, const BvhConfig& config = {},
                     const BinnedSahSchedule& schedule = {});
};

}  // namespace vkrt
