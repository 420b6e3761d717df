// The build-time BVH: nodes with their bounds and the primitive order the leaves refer to. Children are
// allocated in pairs (right = left + 1), the layout the GPU walks; flat_bvh.h turns it into 32-byte nodes.
#pragma once

#include <cstdint>
#include <vector>

#include "common/large_buffer.h"
#include "scene/scene.h"
#include "shared.h"

namespace vkrt {

struct BvhConfig {
    int binCount = 16;    // SAH bins per axis (Wald 2007: 16 is close to a full sweep)
    int maxLeafSize = 4;  // leaves never hold more primitives than this
    int maxDepth = VKRT_BVH_MAX_DEPTH;  // levels, root included: the walks' stacks hold this many
    float traversalCost = 1.0f;
    float intersectionCost = 1.0f;
    int threads = 0;  // 0: all hardware threads
};

struct BvhBuildNode {
    Aabb bounds;
    uint32_t leftOrFirst =
        0;  // interior: index of the left child (the right one follows); leaf: first primitive
    uint32_t primCount = 0;  // 0 for interior nodes
    bool isLeaf() const { return primCount > 0; }
};

struct Bvh {
    HugePageVector<BvhBuildNode> nodes;    // nodes[0] is the root
    HugePageVector<uint32_t> primIndices;  // leaves refer to ranges of this array
};

struct BvhStats {
    double buildMs = 0.0;
    size_t nodes = 0;
    size_t leaves = 0;
    int depth = 0;  // levels, root included
    double sahCost = 0.0;
};

// Depth, node counts and SAH cost (the expected cost of a random ray, relative to one root-box test).
BvhStats measureBvh(const Bvh& bvh, const BvhConfig& config);

}  // namespace vkrt
