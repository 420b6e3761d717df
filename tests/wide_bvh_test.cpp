// The 4-wide GPU layout (flat_bvh.h's collapseToWide): every primitive in exactly one leaf, the leaves the
// binary tree's, every node reached once, and every quantized child box, decoded as the GPU decodes it,
// containing the primitives below it, on inputs that stress the 8-bit grid.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/flat_bvh.h"
#include "bvh/triangle_bvh.h"
#include "scene/procedural_meshes.h"

namespace vkrt {
namespace {

struct WideStats {
    int depth = 0;
    int maxPending = 0;  // the most stack entries a walk can hold (three per level at most)
};

// Walks the wide tree; each failure names the node and slot.
void expectValidWideBvh(std::span<const Aabb> bounds, const BvhConfig& config = {},
                        WideStats* out = nullptr) {
    const FlatBvh flat = flatten(BinnedSahBuilder::build(bounds, config));
    const std::vector<gpu::WideBvhNode> wide = collapseToWide(flat);
    WideStats stats;
    std::vector<int> seen(bounds.size(), 0), reached(wide.size(), 0);
    // Binary leaves by their first primitive: wide leaves must be exactly these ranges.
    std::vector<uint32_t> binaryCount(flat.primIndices.size() + 1, 0);
    for (const gpu::BvhNode& n : flat.nodes)
        if (n.primCount > 0) binaryCount[n.leftOrFirst] = n.primCount;
    struct Entry {
        uint32_t node;
        int level, pending;
    };
    std::vector<Entry> stack{{0u, 1, 0}};
    reached[0] = 1;
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        stats.depth = std::max(stats.depth, e.level);
        stats.maxPending = std::max(stats.maxPending, e.pending);
        const gpu::WideBvhNode& node = wide[e.node];
        int children = 0;
        for (int slot = 0; slot < 4; ++slot) children += wideChildLink(node, slot) != VKRT_WIDE_EMPTY;
        EXPECT_GE(children, bounds.empty() ? 0 : 1) << "node " << e.node;
        for (int slot = 0; slot < 4; ++slot) {
            const uint32_t link = wideChildLink(node, slot);
            if (link == VKRT_WIDE_EMPTY) continue;
            const Aabb box = wideChildBounds(node, slot);
            for (int axis = 0; axis < 3; ++axis) {
                EXPECT_TRUE(std::isfinite(box.min[axis])) << "node " << e.node << " slot " << slot;
            }
            // The primitives below this child, which its decoded box must contain.
            std::vector<uint32_t> below;
            const uint32_t count = link >> VKRT_WIDE_COUNT_SHIFT;
            if (count > 0) {
                const uint32_t first = link & VKRT_WIDE_INDEX_MASK;
                EXPECT_EQ(binaryCount[first], count) << "node " << e.node << " slot " << slot << ": not a binary leaf";
                for (uint32_t i = first; i < first + count; ++i) below.push_back(flat.primIndices[i]);
            } else {
                ASSERT_LT(link, wide.size()) << "node " << e.node << " slot " << slot;
                EXPECT_EQ(reached[link]++, 0) << "node " << link << " reached twice";
                std::vector<uint32_t> nodes{link};
                while (!nodes.empty()) {
                    const gpu::WideBvhNode& n = wide[nodes.back()];
                    nodes.pop_back();
                    for (int s = 0; s < 4; ++s) {
                        const uint32_t l = wideChildLink(n, s);
                        if (l == VKRT_WIDE_EMPTY) continue;
                        if ((l >> VKRT_WIDE_COUNT_SHIFT) == 0) {
                            nodes.push_back(l);
                            continue;
                        }
                        for (uint32_t i = l & VKRT_WIDE_INDEX_MASK; i < (l & VKRT_WIDE_INDEX_MASK) + (l >> VKRT_WIDE_COUNT_SHIFT); ++i)
                            below.push_back(flat.primIndices[i]);
                    }
                }
                stack.push_back({link, e.level + 1, e.pending + children - 1});
            }
            for (uint32_t prim : below) {
                if (count > 0) ++seen[prim];
                EXPECT_TRUE(box.contains(bounds[prim]))
                    << "node " << e.node << " slot " << slot << " does not contain primitive " << prim;
            }
        }
    }
    for (size_t node = 1; node < wide.size(); ++node) EXPECT_EQ(reached[node], 1) << "node " << node;
    for (size_t prim = 0; prim < seen.size(); ++prim) ASSERT_EQ(seen[prim], 1) << "primitive " << prim;
    EXPECT_LE(stats.depth, VKRT_BVH_MAX_DEPTH);
    EXPECT_LE(stats.maxPending, 3 * VKRT_BVH_MAX_DEPTH) << "the GPU's stack";
    if (out) *out = stats;
}

TEST(WideBvh, SphereMesh) {
    WideStats stats;
    expectValidWideBvh(triangleBounds(makeUvSphere(glm::vec3(0.0f), 1.0f, 64, 128)), {}, &stats);
    EXPECT_LE(stats.depth, 12) << "four children a node: about half the binary tree's depth";
}

TEST(WideBvh, TriangleSoupWithSmallDepthLimit) {
    BvhConfig config;
    config.maxDepth = 14;
    expectValidWideBvh(triangleBounds(makeTriangleSoup(20000, 3)), config);
}

TEST(WideBvh, SingleEmptyAndIdenticalInputs) {
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0};
    expectValidWideBvh(triangleBounds({t}));
    expectValidWideBvh(triangleBounds(std::vector<Triangle>(1000, t)));
    const std::vector<gpu::WideBvhNode> none = collapseToWide(flatten(BinnedSahBuilder::build({})));
    ASSERT_EQ(none.size(), 1u);
    for (int slot = 0; slot < 4; ++slot) EXPECT_EQ(wideChildLink(none[0], slot), VKRT_WIDE_EMPTY);
}

// The grid's hard cases: a flat axis (zero extent), a huge triangle beside tiny ones, scenes far from the
// origin, bounds across zero at denormal size, and exponentially spread triangles.
TEST(WideBvh, QuantizationStaysConservative) {
    std::vector<Triangle> triangles;
    for (int i = 0; i < 200; ++i) {
        const float x = 0.01f * i;
        triangles.push_back({{x, 0, 0}, {x + 0.01f, 0, 0}, {x, 0, 0.01f}, 0});  // all in the plane y = 0
    }
    triangles.push_back({{-1e5f, -1e5f, 0}, {1e5f, -1e5f, 0}, {0, 1e5f, 0}, 0});
    for (int i = 0; i < 100; ++i) {
        const float d = 1e-42f * static_cast<float>(i - 50);  // denormal coordinates on both sides of zero
        triangles.push_back({{d, -d, 0}, {d, d, 1e-40f}, {-d, 0, -1e-41f}, 0});
    }
    expectValidWideBvh(triangleBounds(triangles));

    std::vector<Triangle> far;
    for (int i = 0; i < 500; ++i) {
        const float x = 1e6f + 0.125f * static_cast<float>(i);
        far.push_back({{x, 1e6f, -1e6f}, {x + 0.0625f, 1e6f, -1e6f}, {x, 1e6f + 0.0625f, -1e6f}, 0});
    }
    expectValidWideBvh(triangleBounds(far));

    std::vector<Triangle> spread;
    for (int i = 0; i < 3000; ++i) {
        const float x = std::ldexp(1.0f, i % 100) * (1.0f + i / 100);
        spread.push_back({{x, 0, 0}, {x, 1, 0}, {x, 0, 1}, 0});
    }
    expectValidWideBvh(triangleBounds(spread));
}

TEST(WideBvh, QuantizedBoxesStayTight) {
    // Children's decoded boxes grow by at most two grid steps of their parent's box per side.
    const std::vector<Triangle> triangles = makeUvSphere(glm::vec3(3.0f, -2.0f, 1.0f), 2.0f, 32, 64);
    const FlatBvh flat = flatten(BinnedSahBuilder::build(triangleBounds(triangles)));
    const std::vector<gpu::WideBvhNode> wide = collapseToWide(flat);
    double decodedArea = 0.0, exactArea = 0.0;
    for (const gpu::WideBvhNode& node : wide) {
        for (int slot = 0; slot < 4; ++slot) {
            const uint32_t link = wideChildLink(node, slot);
            if (link == VKRT_WIDE_EMPTY) continue;
            decodedArea += wideChildBounds(node, slot).surfaceArea();
            Aabb exact;
            if (link >> VKRT_WIDE_COUNT_SHIFT) {
                for (uint32_t i = link & VKRT_WIDE_INDEX_MASK; i < (link & VKRT_WIDE_INDEX_MASK) + (link >> VKRT_WIDE_COUNT_SHIFT); ++i)
                    exact.grow(triangles[flat.primIndices[i]].bounds());
            } else {
                for (int s = 0; s < 4; ++s)
                    if (wideChildLink(wide[link], s) != VKRT_WIDE_EMPTY) exact.grow(wideChildBounds(wide[link], s));
            }
            exactArea += exact.surfaceArea();
        }
    }
    EXPECT_LT(decodedArea, 1.15 * exactArea) << "8-bit boxes should cost little SAH";
}

}  // namespace
}  // namespace vkrt
