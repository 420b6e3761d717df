// BVH invariants and closest-hit queries against brute force.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_traversal.h"
#include "bvh/flat_bvh.h"
#include "bvh/sah_small_split.h"
#include "bvh/triangle_bvh.h"
#include "cpu/triangle_intersection.h"
#include "random.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

// Every structural promise the GPU relies on, each failure naming the node.
void expectValidBvh(const Bvh& bvh, std::span<const Aabb> bounds, const BvhConfig& config) {
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

// The tree as a sequence independent of node numbering: depth-first, left child first, each node's bounds
// and, for a leaf, its primitives.
std::vector<std::string> canonicalTree(const Bvh& bvh) {
    std::vector<std::string> out;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BvhBuildNode& node = bvh.nodes[stack.back()];
        stack.pop_back();
        std::string line;
        for (float v : {node.bounds.min.x, node.bounds.min.y, node.bounds.min.z, node.bounds.max.x,
                        node.bounds.max.y, node.bounds.max.z}) {
            line.append(std::to_string(std::bit_cast<uint32_t>(v))).append(" ");
        }
        if (node.isLeaf()) {
            std::vector<uint32_t> prims(bvh.primIndices.begin() + node.leftOrFirst,
                                        bvh.primIndices.begin() + node.leftOrFirst + node.primCount);
            std::sort(prims.begin(), prims.end());
            line += "leaf";
            for (uint32_t p : prims) line.append(" ").append(std::to_string(p));
        } else {
            stack.push_back(node.leftOrFirst + 1);
            stack.push_back(node.leftOrFirst);
        }
        out.push_back(line);
    }
    return out;
}

void expectSameTree(const Bvh& a, const Bvh& b, const char* what) {
    const std::vector<std::string> ca = canonicalTree(a), cb = canonicalTree(b);
    ASSERT_EQ(ca.size(), cb.size()) << what;
    for (size_t i = 0; i < ca.size(); ++i)
        ASSERT_EQ(ca[i], cb[i]) << what << ": node " << i << " in depth-first order";
}

// The binned SAH build as first written (Wald 2007, one recursive function, 16 bins swept in full): the
// fast builder must make exactly its tree.
class ReferenceBuilder {
  public:
    ReferenceBuilder(std::span<const Aabb> bounds, const BvhConfig& config)
        : bounds_(bounds), config_(config) {
        for (const Aabb& b : bounds) centers_.push_back(b.center());
    }
    Bvh build() {
        bvh_.primIndices.resize(bounds_.size());
        for (uint32_t i = 0; i < bounds_.size(); ++i) bvh_.primIndices[i] = i;
        bvh_.nodes.emplace_back();
        buildNode(0, 0, static_cast<uint32_t>(bounds_.size()), 1);
        return bvh_;
    }

  private:
    int levelsNeeded(uint32_t count) const {
        int levels = 1;
        for (uint64_t capacity = config_.maxLeafSize; capacity < count; capacity *= 2) ++levels;
        return levels;
    }
    int binOf(const glm::vec3& c, const Aabb& cb, int axis) const {
        const float extent = cb.max[axis] - cb.min[axis];
        return std::clamp(
            static_cast<int>((c[axis] - cb.min[axis]) * (static_cast<float>(config_.binCount) / extent)), 0,
            config_.binCount - 1);
    }
    void buildNode(uint32_t nodeIndex, uint32_t begin, uint32_t end, int level) {
        Aabb nodeBounds, cb;
        for (uint32_t i = begin; i < end; ++i) {
            nodeBounds.grow(bounds_[bvh_.primIndices[i]]);
            cb.grow(centers_[bvh_.primIndices[i]]);
        }
        bvh_.nodes[nodeIndex].bounds = nodeBounds;
        const uint32_t count = end - begin;
        auto leaf = [&] {
            bvh_.nodes[nodeIndex].leftOrFirst = begin;
            bvh_.nodes[nodeIndex].primCount = count;
        };
        if (count <= 1) return leaf();
        const bool mustBalance = level - 1 + levelsNeeded(count) >= config_.maxDepth;
        uint32_t middle = begin;
        if (!mustBalance) {
            int bestAxis = -1, bestBin = 0;
            float bestCost = std::numeric_limits<float>::infinity();
            const float nodeArea = nodeBounds.surfaceArea();
            for (int axis = 0; axis < 3; ++axis) {
                if (!(cb.max[axis] > cb.min[axis])) continue;
                std::vector<Aabb> bins(config_.binCount);
                std::vector<uint32_t> counts(config_.binCount, 0);
                for (uint32_t i = begin; i < end; ++i) {
                    const int b = binOf(centers_[bvh_.primIndices[i]], cb, axis);
                    bins[b].grow(bounds_[bvh_.primIndices[i]]);
                    ++counts[b];
                }
                for (int b = 0; b < config_.binCount - 1; ++b) {
                    Aabb left, right;
                    uint32_t nl = 0, nr = 0;
                    for (int k = 0; k <= b; ++k) left.grow(bins[k]), nl += counts[k];
                    for (int k = b + 1; k < config_.binCount; ++k) right.grow(bins[k]), nr += counts[k];
                    if (nl == 0 || nr == 0) continue;
                    const float cost = config_.traversalCost +
                                       config_.intersectionCost *
                                           (left.surfaceArea() * nl + right.surfaceArea() * nr) / nodeArea;
                    if (cost < bestCost) bestAxis = axis, bestBin = b, bestCost = cost;
                }
            }
            if (count <= static_cast<uint32_t>(config_.maxLeafSize) &&
                config_.intersectionCost * static_cast<float>(count) <= bestCost) {
                return leaf();
            }
            if (bestAxis >= 0) {
                middle = static_cast<uint32_t>(
                    std::partition(bvh_.primIndices.begin() + begin, bvh_.primIndices.begin() + end,
                                   [&](uint32_t p) { return binOf(centers_[p], cb, bestAxis) <= bestBin; }) -
                    bvh_.primIndices.begin());
            }
        } else if (count <= static_cast<uint32_t>(config_.maxLeafSize)) {
            return leaf();
        }
        if (middle == begin) {  // median split, ties by index
            middle = begin + count / 2;
            const glm::vec3 e = cb.extent();
            const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
            if (e[axis] > 0.0f) {
                std::nth_element(bvh_.primIndices.begin() + begin, bvh_.primIndices.begin() + middle,
                                 bvh_.primIndices.begin() + end, [&](uint32_t a, uint32_t b) {
                                     return centers_[a][axis] < centers_[b][axis] ||
                                            (centers_[a][axis] == centers_[b][axis] && a < b);
                                 });
            }
        }
        const uint32_t left = static_cast<uint32_t>(bvh_.nodes.size());
        bvh_.nodes.resize(left + 2);
        bvh_.nodes[nodeIndex].leftOrFirst = left;
        bvh_.nodes[nodeIndex].primCount = 0;
        buildNode(left, begin, middle, level + 1);
        buildNode(left + 1, middle, end, level + 1);
    }

    std::span<const Aabb> bounds_;
    const BvhConfig& config_;
    std::vector<glm::vec3> centers_;
    Bvh bvh_;
};

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
    const HugePageVector<Aabb> bounds = triangleBounds(triangles);
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
    const auto bounds = triangleBounds(triangles);
    const BvhConfig config;
    expectValidBvh(BinnedSahBuilder::build(bounds, config), bounds, config);
}

TEST(Bvh, InvariantsOnTriangleSoupWithSmallDepthLimit) {
    const auto triangles = makeTriangleSoup(20000, 3);
    const auto bounds = triangleBounds(triangles);
    BvhConfig config;
    config.maxDepth = 14;  // forces median splits near the limit
    const Bvh bvh = BinnedSahBuilder::build(bounds, config);
    expectValidBvh(bvh, bounds, config);
    EXPECT_LE(measureBvh(bvh, config).depth, 14);
}

TEST(Bvh, DepthBoundHoldsForIdenticalTriangles) {
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0};
    const std::vector<Triangle> triangles(100000, t);
    const auto bounds = triangleBounds(triangles);
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
    const auto bounds = triangleBounds(triangles);
    BvhConfig config;
    config.maxDepth = 20;
    expectValidBvh(BinnedSahBuilder::build(bounds, config), bounds, config);
}

TEST(Bvh, SingleAndEmptyInputs) {
    const std::vector<Triangle> one{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0}};
    const Bvh bvh = BinnedSahBuilder::build(triangleBounds(one));
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
    const auto bounds = triangleBounds(makeTriangleSoup(100000, 11));
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

// Node for node, bit for bit: the same nodes, bounds, leaves and primitive order for 1, 2, 3 and 8 threads
// (the top of this tree is split by all threads, block by block).
TEST(Bvh, SameTreeForEveryThreadCount) {
    const auto bounds = triangleBounds(makeUvSphere(glm::vec3(0.0f), 1.0f, 200, 400));
    BvhConfig config;
    config.threads = 1;
    const Bvh serial = BinnedSahBuilder::build(bounds, config);
    for (int threads : {2, 3, 8}) {
        config.threads = threads;
        const Bvh parallel = BinnedSahBuilder::build(bounds, config);
        ASSERT_EQ(parallel.nodes.size(), serial.nodes.size()) << threads << " threads";
        for (size_t i = 0; i < serial.nodes.size(); ++i) {
            const BvhBuildNode &a = serial.nodes[i], &b = parallel.nodes[i];
            ASSERT_TRUE(a.bounds.min == b.bounds.min && a.bounds.max == b.bounds.max &&
                        a.leftOrFirst == b.leftOrFirst && a.primCount == b.primCount)
                << "node " << i << ", " << threads << " threads";
        }
        EXPECT_EQ(parallel.primIndices, serial.primIndices) << threads << " threads";
    }
}

// Parallel binning and partitioning at the top (block sums of bins, stable partition into a second array)
// make exactly the tree of the plain recursive builder, with leaves in ascending primitive order.
TEST(Bvh, SameTreeAsTheReferenceBuilder) {
    struct Case {
        const char* name;
        std::vector<Triangle> triangles;
        int maxDepth;
    };
    const Case cases[] = {{"sphere", makeUvSphere(glm::vec3(0.0f), 1.0f, 64, 128), 64},
                          {"soup", makeTriangleSoup(20000, 3), 64},
                          {"soup, depth 14 (median splits)", makeTriangleSoup(20000, 3), 14}};
    for (const Case& c : cases) {
        const auto bounds = triangleBounds(c.triangles);
        BvhConfig config;
        config.maxDepth = c.maxDepth;
        config.threads = 2;
        const Bvh reference = ReferenceBuilder(bounds, config).build();
        for (const BinnedSahSchedule schedule :
             {BinnedSahSchedule{}, BinnedSahSchedule{64, 100}, BinnedSahSchedule{1000, 7}}) {
            std::string trace = c.name;
            trace.append(", subtrees of ").append(std::to_string(schedule.subtreeSize));
            trace.append(", blocks of ").append(std::to_string(schedule.blockSize));
            SCOPED_TRACE(trace);
            const Bvh bvh = BinnedSahBuilder::build(bounds, config, schedule);
            expectValidBvh(bvh, bounds, config);
            expectSameTree(bvh, reference, c.name);
        }
    }
}

// The split of a few primitives without bins (sah_small_split.h) is the one binning finds: same axis, bin and
// cost, bit for bit, and the same bounds on each side. Random subsets of a soup, with duplicated primitives
// and flat sets (an axis without extent) among them.
TEST(Bvh, SmallNodeSplitMatchesBinning) {
    using namespace sah;
    const auto soup = triangleBounds(makeTriangleSoup(4000, 9, 0.3f));
    const BvhConfig config;
    Bins bins(config.binCount);
    SmallNodeSplit small;
    std::vector<float> rightArea;
    std::vector<uint32_t> rightCount;
    int splits = 0;
    for (uint32_t trial = 0; trial < 3000; ++trial) {
        auto r = [&](uint32_t d) { return vkrtRandom(21, trial, 0, d); };
        const uint32_t count = 2 + trial % (SmallNodeSplit::kMaxCount - 1);
        std::vector<PrimRef> refs;
        Box4 bounds, centers;
        for (uint32_t i = 0; i < count; ++i) {
            // Every third trial repeats primitives; every fifth flattens them onto x = 0.5.
            const uint32_t index =
                static_cast<uint32_t>(r(i) * (trial % 3 == 0 ? 3 : soup.size())) % soup.size();
            Aabb box = soup[index];
            if (trial % 5 == 0) box.min.x = box.max.x = 0.5f;
            refs.push_back(makePrimRef(box, index));
            bounds.grow(refs.back().min, refs.back().max);
            centers.grow(refs.back().doubledCenter());
        }
        const BinMapping mapping(centers, config.binCount);
        bins.clear();
        bins.add(refs.data(), 0, count, mapping);
        const Split binned = findSahSplit(bins, bounds.toAabb(), centers, config, rightArea, rightCount);
        const Split found = small.find(refs.data(), count, mapping, bounds.toAabb(), centers, config);
        ASSERT_EQ(found.axis, binned.axis) << "trial " << trial;
        if (binned.axis < 0) continue;
        ++splits;
        ASSERT_EQ(found.bin, binned.bin) << "trial " << trial;
        ASSERT_EQ(std::bit_cast<uint32_t>(found.cost), std::bit_cast<uint32_t>(binned.cost))
            << "trial " << trial;
        Aabb left, right;
        splitBounds(bins, binned, left, right);
        EXPECT_TRUE(small.leftBounds().min == left.min && small.leftBounds().max == left.max)
            << "trial " << trial;
        EXPECT_TRUE(small.rightBounds().min == right.min && small.rightBounds().max == right.max)
            << "trial " << trial;
        for (uint32_t i = 0; i < count; ++i) {
            EXPECT_EQ(small.goesLeft(i, found), mapping.binsOf(refs[i])[found.axis] <= found.bin)
                << "trial " << trial << ", primitive " << i;
        }
    }
    EXPECT_GT(splits, 2000);
}

// The branch-free partition: each side gets its references in the order they come (the right side
// reversed when written downwards), and each side's centroid bounds are those of its references.
TEST(Bvh, PartitionKeepsOrderAndGathersCentroidBounds) {
    using namespace sah;
    const auto soup = triangleBounds(makeTriangleSoup(1000, 13));
    std::vector<PrimRef> refs;
    for (uint32_t i = 0; i < soup.size(); ++i) refs.push_back(makePrimRef(soup[i], i));
    auto goesLeft = [&](uint32_t i) { return refs[i].doubledCenter()[1] < 1.0f; };
    for (const ptrdiff_t step : {ptrdiff_t{1}, ptrdiff_t{-1}}) {
        std::vector<uint32_t> expectedLeft, expectedRight;
        Box4 expectedLeftCenters, expectedRightCenters;
        for (uint32_t i = 0; i < refs.size(); ++i) {
            (goesLeft(i) ? expectedLeft : expectedRight).push_back(i);
            (goesLeft(i) ? expectedLeftCenters : expectedRightCenters).grow(refs[i].doubledCenter());
        }
        std::vector<PrimRef> out(refs.size());
        const uint32_t leftCount = static_cast<uint32_t>(expectedLeft.size());
        PrimRef* rightOut = step > 0 ? out.data() + leftCount : out.data() + out.size() - 1;
        Box4 leftCenters, rightCenters;
        ASSERT_EQ(partitionRefs(refs.data(), 0, static_cast<uint32_t>(refs.size()), out.data(), rightOut,
                                step, leftCenters, rightCenters, goesLeft),
                  leftCount);
        for (uint32_t k = 0; k < leftCount; ++k) ASSERT_EQ(out[k].index(), expectedLeft[k]) << "left " << k;
        for (uint32_t k = 0; k < expectedRight.size(); ++k) {
            const size_t at = step > 0 ? leftCount + k : out.size() - 1 - k;
            ASSERT_EQ(out[at].index(), expectedRight[k]) << "right " << k << ", step " << step;
        }
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_EQ(leftCenters.min[axis], expectedLeftCenters.min[axis]);
            EXPECT_EQ(leftCenters.max[axis], expectedLeftCenters.max[axis]);
            EXPECT_EQ(rightCenters.min[axis], expectedRightCenters.min[axis]);
            EXPECT_EQ(rightCenters.max[axis], expectedRightCenters.max[axis]);
        }
    }
}

// The centroid that binning reads leaves out the index kept in lane 3 of a reference (read as a float, it
// is a denormal for indices below 2^23, and arithmetic on it is slow).
TEST(Bvh, DoubledCenterHoldsNoIndex) {
    const sah::PrimRef ref = sah::makePrimRef(Aabb{{1, 2, 3}, {2, 4, 8}}, 12345);
    const sah::Float4 center = ref.doubledCenter();
    EXPECT_EQ(ref.index(), 12345u);
    EXPECT_EQ(center[0], 3.0f);
    EXPECT_EQ(center[1], 6.0f);
    EXPECT_EQ(center[2], 11.0f);
    EXPECT_EQ(std::bit_cast<uint32_t>(center[3]), 0u);
}

// Bounds computed in parallel blocks are each triangle's, in order, for any thread count.
TEST(Bvh, TriangleBoundsForEveryThreadCount) {
    const auto triangles = makeTriangleSoup(200000, 4);
    for (int threads : {1, 2, 3}) {
        const HugePageVector<Aabb> bounds = triangleBounds(triangles, threads);
        ASSERT_EQ(bounds.size(), triangles.size());
        for (size_t i = 0; i < triangles.size(); ++i) {
            const Aabb expected = triangles[i].bounds();
            ASSERT_TRUE(bounds[i].min == expected.min && bounds[i].max == expected.max)
                << "triangle " << i << ", " << threads << " threads";
        }
    }
    EXPECT_TRUE(triangleBounds({}, 2).empty());
}

TEST(Bvh, SahCostOfASingleLeafIsItsPrimitiveCount) {
    const std::vector<Triangle> two{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0},
                                    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0}};
    const BvhConfig config;
    const Bvh bvh = BinnedSahBuilder::build(triangleBounds(two), config);
    EXPECT_DOUBLE_EQ(measureBvh(bvh, config).sahCost, 2.0);  // identical centroids: one leaf of two
}

// A scene wider than about 1e19 has a root area beyond float: the cost, measured in double, stays finite (it
// came out NaN, and the stats wrote null).
TEST(Bvh, SahCostOfAVeryWideSceneIsFinite) {
    const std::vector<Triangle> wide{{{-3e20f, 0, 0}, {-3e20f, 1e20f, 0}, {-3e20f, 0, 1e20f}, 0},
                                     {{3e20f, 0, 0}, {3e20f, 1e20f, 0}, {3e20f, 0, 1e20f}, 0}};
    const BvhConfig config;
    const Bvh bvh = BinnedSahBuilder::build(triangleBounds(wide), config);
    const double cost = measureBvh(bvh, config).sahCost;
    EXPECT_TRUE(std::isfinite(cost)) << cost;
    EXPECT_GT(cost, 0.0);
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
