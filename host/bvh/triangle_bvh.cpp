#include "bvh/triangle_bvh.h"

#include <chrono>

#include "bvh/binned_sah_builder.h"

namespace vkrt {

TriangleBvh buildTriangleBvh(const std::vector<Triangle>& triangles, const BvhConfig& config) {
    std::vector<Aabb> bounds(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) bounds[i] = triangles[i].bounds();
    const auto start = std::chrono::steady_clock::now();
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    const double buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    TriangleBvh result{flatten(bvh), measureBvh(bvh, config)};
    result.stats.buildMs = buildMs;
    return result;
}

}  // namespace vkrt
