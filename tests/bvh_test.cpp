// BVH invariants and closest-hit queries against brute force.
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_traversal.h"
#include "bvh/flat_bvh.h"
#include "cpu/triangle_intersection.h"
#include "random.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

std::vector<Aabb> boundsOf(const std::vector<Triangle>& triangles) {
    std::vector<Aabb> bounds(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) bounds[i] = triangles[i].bounds();
    return bounds;
}

// Every structural promise the GPU relies on, each failure naming the node.
void expectValidBvh(const Bvh& bvh, const std::vector<Aabb>& bounds, const BvhConfig& config) {
    std::vector<int> seen(bounds.size(), 0);
    std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
    int depth = 0;
    size_t visited = 0;
    while (!stack.empty()) {
        auto [index, level] = stack.back();
        stack.pop_back();
        ++visited;
        ASSERT_LT(index, bvh.nodes.size());
        const BvhBuildNode& node = bvh.nodes[index];
        depth = std::max(depth, level);
        if (node.isLeaf()) {
            EXPECT_LE(node.primCount, static_cast<uint32_t>(config.maxLeafSize)) << "leaf " << index;
            for (uint32_t i = 0; i < node.primCount; ++i) {
                const uint32_t prim = bvh.primIndices[node.leftOrFirst + i];
                ++seen[prim];
                EXPECT_TRUE(node.bounds.contains(bounds[prim]))
                    << "leaf " << index << " does not contain " << prim;
            }
        } else {
            for (uint32_t child : {node.leftOrFirst, node.leftOrFirst + 1}) {
                ASSERT_LT(child, bvh.nodes.size());
                EXPECT_TRUE(node.bounds.contains(bvh.nodes[child].bounds))
                    << "child " << child << " of " << index;
                stack.push_back({child, level + 1});
            }
        }
    }
    EXPECT_EQ(visited, bvh.nodes.size()) << "every node is reachable exactly once";
    EXPECT_LE(depth, config.maxDepth);
    for (size_t prim = 0; prim < seen.size(); ++prim) {
        ASSERT_EQ(seen[prim], 1) << "primitive " << prim << " must be in exactly one leaf";
    }
}

struct Closest {
    uint32_t prim = std::numeric_limits<uint32_t>::max();
    double t = std::numeric_limits<double>::infinity();
};

Closest bruteForce(const std::vector<Triangle>& triangles, const RayT<double>& ray) {
    Closest best;
    for (uint32_t i = 0; i < triangles.size(); ++i) {
        TriangleHit hit;
        if (intersectTriangle(triangles[i], ray.origin, ray.direction, 0.0, best.t, hit)) best = {i, hit.t};
    }
    return best;
}

Closest throughBvh(const std::vector<Triangle>& triangles, const FlatBvh& bvh, const RayT<double>& ray) {
    Closest best;
    traverseBvh(bvh, ray, 0.0, best.t, [&](uint32_t prim, double& tMax) {
        TriangleHit hit;
        if (intersectTriangle(triangles[prim], ray.origin, ray.direction, 0.0, tMax, hit)) {
            tMax = hit.t;
            best.prim = prim;
        }
        return false;
    });
    return best;
}

// Rays from random points around the mesh towards random points inside its bounds; most hit.
void expectClosestHitsMatchBruteForce(const std::vector<Triangle>& triangles, int rayCount,
                                      const char* name) {
    const std::vector<Aabb> bounds = boundsOf(triangles);
    const FlatBvh bvh = flatten(BinnedSahBuilder::build(bounds));
    Aabb all;
    for (const Aabb& b : bounds) all.grow(b);
    const glm::dvec3 lo(all.min), extent(all.extent());
    int hits = 0, ties = 0;
    for (int i = 0; i < rayCount; ++i) {
        auto r = [&](uint32_t d) {
            return static_cast<double>(vkrtRandom(7, static_cast<uint32_t>(i), 0, d));
        };
        const glm::dvec3 origin = lo + extent * glm::dvec3(3 * r(0) - 1, 3 * r(1) - 1, 3 * r(2) - 1);
        const glm::dvec3 target = lo + extent * glm::dvec3(r(3), r(4), r(5));
        const RayT<double> ray{origin, glm::normalize(target - origin)};
        const Closest expected = bruteForce(triangles, ray);
        const Closest actual = throughBvh(triangles, bvh, ray);
        ASSERT_EQ(expected.t, actual.t) << name << " ray " << i;
        if (expected.prim != actual.prim) ++ties;  // same distance, another triangle: a tie, allowed
        hits += std::isfinite(expected.t) ? 1 : 0;
    }
    EXPECT_GT(hits, rayCount / 10) << name << ": the test rays should mostly hit";
    EXPECT_LT(ties, rayCount / 100) << name;
}

TEST(Bvh, InvariantsOnSphereMesh) {
    const auto triangles = makeUvSphere(glm::vec3(0.0f), 1.0f, 64, 128);
    const auto bounds = boundsOf(triangles);
    const BvhConfig config;
    expectValidBvh(BinnedSahBuilder::build(bounds, config), bounds, config);
}

TEST(Bvh, InvariantsOnTriangleSoupWithSmallDepthLimit) {
    const auto triangles = makeTriangleSoup(20000, 3);
    const auto bounds = boundsOf(triangles);
    BvhConfig config;
    config.maxDepth = 14;  // forces median splits near the limit
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    expectValidBvh(bvh, bounds, config);
    EXPECT_LE(measureBvh(bvh, config).depth, 14);
}

TEST(Bvh, DepthBoundHoldsForIdenticalTriangles) {
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0};
    const std::vector<Triangle> triangles(100000, t);
    const auto bounds = boundsOf(triangles);
    const BvhConfig config;
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    expectValidBvh(bvh, bounds, config);
    EXPECT_LE(measureBvh(bvh, config).depth, VKRT_BVH_MAX_DEPTH);
    const FlatBvh flat = flatten(bvh);
    const Closest hit = throughBvh(triangles, flat, {{0.25, 0.25, 1.0}, {0.0, 0.0, -1.0}});
    EXPECT_DOUBLE_EQ(hit.t, 1.0);
}

TEST(Bvh, DepthBoundHoldsForAPathologicalChain) {
    // Triangles at exponentially growing distances make SAH peel one primitive at a time.
    std::vector<Triangle> triangles;
    for (int i = 0; i < 3000; ++i) {
        const float x = std::ldexp(1.0f, i % 100) * (1.0f + i / 100);
        triangles.push_back({{x, 0, 0}, {x, 1, 0}, {x, 0, 1}, 0});
    }
    const auto bounds = boundsOf(triangles);
    BvhConfig config;
    config.maxDepth = 20;
    expectValidBvh(BinnedSahBuilder::build(bounds, config), bounds, config);
}

TEST(Bvh, SingleAndEmptyInputs) {
    const std::vector<Triangle> one{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0}};
    const Bvh bvh = BinnedSahBuilder::build(boundsOf(one));
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_TRUE(bvh.nodes[0].isLeaf());
    const FlatBvh empty = flatten(BinnedSahBuilder::build({}));
    EXPECT_TRUE(empty.empty());
    double tMax = 1e30;
    int visits = 0;
    traverseBvh(empty, RayT<double>{{0, 0, 0}, {0, 0, 1}}, 0.0, tMax, [&](uint32_t, double&) {
        ++visits;
        return false;
    });
    EXPECT_EQ(visits, 0);
}

TEST(Bvh, ParallelAndSerialBuildsAgree) {
    const auto bounds = boundsOf(makeTriangleSoup(100000, 11));
    BvhConfig serial;
    serial.threads = 1;
    BvhConfig parallel;
    parallel.threads = 2;
    const BvhStats a = measureBvh(BinnedSahBuilder::build(bounds, serial), serial);
    const BvhStats b = measureBvh(BinnedSahBuilder::build(bounds, parallel), parallel);
    EXPECT_EQ(a.nodes, b.nodes);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_DOUBLE_EQ(a.sahCost, b.sahCost);
}

TEST(Bvh, SahCostOfASingleLeafIsItsPrimitiveCount) {
    const std::vector<Triangle> two{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0},
                                    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0}};
    const BvhConfig config;
    const Bvh bvh = BinnedSahBuilder::build(boundsOf(two), config);
    EXPECT_DOUBLE_EQ(measureBvh(bvh, config).sahCost, 2.0);  // identical centroids: one leaf of two
}

TEST(BvhTraversal, ClosestHitMatchesBruteForceOnSphere) {
    expectClosestHitsMatchBruteForce(makeUvSphere(glm::vec3(0.5f), 0.4f, 40, 80), 100000, "sphere");
}

TEST(BvhTraversal, ClosestHitMatchesBruteForceOnTriangleSoup) {
    expectClosestHitsMatchBruteForce(makeTriangleSoup(5000, 5, 0.2f), 100000, "soup");
}

TEST(BvhTraversal, ClosestHitMatchesBruteForceOnRealModels) {
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal();
    const std::pair<const char*, int> models[] = {{"khronos-Duck/glTF-Binary/Duck.glb", 100000},
                                                  {"khronos-Suzanne/glTF/Suzanne.gltf", 100000},
                                                  {"cornell-box-nvidia/cornellBox.gltf", 30000}};
    for (const auto& [model, rays] : models) {
        const Scene scene = loadGltf((test::scenesReal() / model).string());
        expectClosestHitsMatchBruteForce(scene.triangles, rays, model);
    }
}

}  // namespace
}  // namespace vkrt
