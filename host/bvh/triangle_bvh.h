// The BVH over a list of triangles, or a scene's primitives, in one call: bounds, binned SAH build,
// measurement and the flatten step.
#pragma once

#include <vector>

#include "bvh/bvh.h"
#include "bvh/flat_bvh.h"
#include "common/large_buffer.h"

namespace vkrt {

struct TriangleBvh {
    FlatBvh flat;
    BvhStats stats;  // buildMs covers the build alone
};

// Each triangle's bounding box, in order: what the builder sorts. Computed on `threads` threads (0: all
// hardware threads), on huge pages.
HugePageVector<Aabb> triangleBounds(const std::vector<Triangle>& triangles, int threads = 0);

TriangleBvh buildTriangleBvh(const std::vector<Triangle>& triangles, const BvhConfig& config = {});

// The BVH over all of a scene's primitives (triangles, then spheres), as the renderers trace them.
TriangleBvh buildSceneBvh(const Scene& scene, const BvhConfig& config = {});

}  // namespace vkrt
