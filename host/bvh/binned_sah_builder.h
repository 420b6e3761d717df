// Binned SAH builder (Wald, "On fast construction of SAH-based bounding volume hierarchies", 2007).
// Subtrees are built in parallel; near the depth limit it falls back to median splits, so the depth bound
// holds for any input, 100k identical triangles included.
#pragma once

#include <span>

#include "bvh/bvh.h"

namespace vkrt {

struct BinnedSahBuilder {
    static Bvh build(std::span<const Aabb> bounds, const BvhConfig& config = {});
};

}  // namespace vkrt
