// The GPU layout of a BVH: 32-byte nodes (shaders/shared.h) and the primitive order of the leaves.
#pragma once

#include <vector>

#include "bvh/bvh.h"
#include "shared.h"

namespace vkrt {

struct FlatBvh {
    std::vector<gpu::BvhNode> nodes;
    std::vector<uint32_t> primIndices;
    bool empty() const { return primIndices.empty(); }
};

// The one flatten step from build-time nodes to the GPU layout. The builder already places children in
// pairs, so node indices carry over unchanged.
FlatBvh flatten(const Bvh& bvh);

}  // namespace vkrt
