// The BVH over a list of triangles in one call: bounds, binned SAH build, measurement and the flatten step.
#pragma once

#include <vector>

#include "bvh/bvh.h"
#include "bvh/flat_bvh.h"

namespace vkrt {

struct TriangleBvh {
    FlatBvh flat;
    BvhStats stats;  // buildMs covers the build alone
};

TriangleBvh buildTriangleBvh(const std::vector<Triangle>& triangles, const BvhConfig& config = {});

}  // namespace vkrt
