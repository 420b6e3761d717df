#include "bvh/triangle_bvh.h"

#include <chrono>

#include "bvh/binned_sah_builder.h"

namespace vkrt {

namespace {

TriangleBvh buildOver(const std::vector<Aabb>& bounds, const BvhConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    const double buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    TriangleBvh result{flatten(bvh), measureBvh(bvh, config)};
    result.stats.buildMs = buildMs;
    return result;
}

}  // namespace

std::vector<Aabb> triangleBounds(const std::vector<Triangle>& triangles) {
    std::vector<Aabb> bounds(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) bounds[i] = triangles[i].bounds();
    return bounds;
}

TriangleBvh buildTriangleBvh(const std::vector<Triangle>& triangles, const BvhConfig& config) {
    return buildOver(triangleBounds(triangles), config);
}

TriangleBvh buildSceneBvh(const Scene& scene, const BvhConfig& config) {
    std::vector<Aabb> bounds(scene.primitiveCount());
    for (uint32_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.boundsOf(i);
    return buildOver(bounds, config);
}

}  // namespace vkrt
