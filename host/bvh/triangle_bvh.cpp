#include "bvh/triangle_bvh.h"

#include <algorithm>
#include <chrono>
#include <span>

#include "bvh/binned_sah_builder.h"
#include "common/parallel_for.h"

namespace vkrt {

namespace {

TriangleBvh buildOver(std::span<const Aabb> bounds, const BvhConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    const double buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    TriangleBvh result{flatten(bvh), measureBvh(bvh, config)};
    result.stats.buildMs = buildMs;
    return result;
}

// The bounds of primitives [0, count), boundsOf(i) for each, in parallel blocks.
template <typename BoundsOf>
HugePageVector<Aabb> primitiveBounds(size_t count, int threads, BoundsOf&& boundsOf) {
    HugePageVector<Aabb> bounds(count);
    constexpr size_t kBlock = 64 * 1024;
    parallelFor((count + kBlock - 1) / kBlock, threadCount(threads), [&](size_t block, unsigned) {
        for (size_t i = block * kBlock, end = std::min(count, i + kBlock); i < end; ++i)
            bounds[i] = boundsOf(i);
    });
    return bounds;
}

}  // namespace

HugePageVector<Aabb> triangleBounds(const std::vector<Triangle>& triangles, int threads) {
    return primitiveBounds(triangles.size(), threads, [&](size_t i) { return triangles[i].bounds(); });
}

TriangleBvh buildTriangleBvh(const std::vector<Triangle>& triangles, const BvhConfig& config) {
    return buildOver(triangleBounds(triangles, config.threads), config);
}

TriangleBvh buildSceneBvh(const Scene& scene, const BvhConfig& config) {
    return buildOver(primitiveBounds(scene.primitiveCount(), config.threads,
                                     [&](size_t i) { return scene.boundsOf(static_cast<uint32_t>(i)); }),
                     config);
}

}  // namespace vkrt
