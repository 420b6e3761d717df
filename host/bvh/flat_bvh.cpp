#include "bvh/flat_bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vkrt {

FlatBvh flatten(const Bvh& bvh) {
    FlatBvh flat;
    flat.nodes.resize(bvh.nodes.size());
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhBuildNode& node = bvh.nodes[i];
        flat.nodes[i] = gpu::BvhNode{node.bounds.min, node.leftOrFirst, node.bounds.max, node.primCount};
    }
    flat.primIndices.assign(bvh.primIndices.begin(), bvh.primIndices.end());
    return flat;
}

namespace {

constexpr int kWidth = 4;

// Float results as a device that flushes denormals (lavapipe) sees them.
float flushDenormal(float x) { return std::abs(x) < std::numeric_limits<float>::min() ? 0.0f * x : x; }

// The grid spacing of a biased exponent, 2^(exponent - 127); exponents stay in [1, 254], so it is normal.
float spacingOf(uint32_t exponent) { return std::ldexp(1.0f, static_cast<int>(exponent) - 127); }

// One bound decoded as the shader does: origin + q * spacing (the product is exact), flushed.
float decodeBound(float origin, uint32_t q, uint32_t exponent) {
    return flushDenormal(origin + static_cast<float>(q) * spacingOf(exponent));
}

uint32_t byteOf(uint32_t word, int slot) { return (word >> (8 * slot)) & 0xffu; }

struct AxisGrid {
    float origin;
    uint32_t exponent;
};

// The grid of one axis over [lo, hi]: an origin the GPU reads unchanged (normal or zero) at or below lo,
// and the smallest spacing whose 255 steps reach hi.
AxisGrid gridOver(float lo, float hi) {
    float origin = flushDenormal(lo);
    if (origin > lo) origin = -std::numeric_limits<float>::min();  // a negative denormal rounds down
    for (uint32_t exponent = 1; exponent <= 254; ++exponent) {
        if (decodeBound(origin, 255u, exponent) >= hi) return {origin, exponent};
    }
    throw std::runtime_error("BVH bounds too large for the wide node's grid");
}

// The largest q whose decoded bound lies at or below lo, and the smallest whose decoded bound lies at or
// above hi: the quantized box contains [lo, hi] on the GPU.
uint32_t quantizeLower(const AxisGrid& g, float lo) {
    const double steps = (static_cast<double>(lo) - g.origin) / spacingOf(g.exponent);
    int64_t q = std::clamp<int64_t>(static_cast<int64_t>(std::floor(steps)), 0, 255);
    while (q > 0 && decodeBound(g.origin, static_cast<uint32_t>(q), g.exponent) > lo) --q;
    return static_cast<uint32_t>(q);
}

uint32_t quantizeUpper(const AxisGrid& g, float hi) {
    const double steps = (static_cast<double>(hi) - g.origin) / spacingOf(g.exponent);
    int64_t q = std::clamp<int64_t>(static_cast<int64_t>(std::ceil(steps)), 0, 255);
    while (q < 255 && decodeBound(g.origin, static_cast<uint32_t>(q), g.exponent) < hi) ++q;
    return static_cast<uint32_t>(q);
}

Aabb boundsOf(const gpu::BvhNode& node) {
    Aabb b;
    b.min = node.boundsMin;
    b.max = node.boundsMax;
    return b;
}

class WideCollapse {
  public:
    explicit WideCollapse(const FlatBvh& bvh) : bvh_(bvh) {}

    // Emits the wide node for binary node `index` and, depth first, those below it; returns its index.
    uint32_t emit(uint32_t index) {
        const uint32_t self = static_cast<uint32_t>(nodes_.size());
        nodes_.emplace_back();
        // The binary node's children, the largest interior one opened until there are four.
        uint32_t slots[kWidth];
        int used = 0;
        const gpu::BvhNode& binary = bvh_.nodes[index];
        if (binary.primCount > 0) {
            slots[used++] = index;  // a leaf root: one child, itself
        } else {
            slots[used++] = binary.leftOrFirst;
            slots[used++] = binary.leftOrFirst + 1;
        }
        while (used < kWidth) {
            int widest = -1;
            float widestArea = -1.0f;
            for (int k = 0; k < used; ++k) {
                const gpu::BvhNode& n = bvh_.nodes[slots[k]];
                const float area = boundsOf(n).surfaceArea();
                if (n.primCount == 0 && area > widestArea) widest = k, widestArea = area;
            }
            if (widest < 0) break;
            const uint32_t opened = slots[widest];
            // The two children take the opened node's place and the next slot, keeping the tree's order.
            for (int k = used; k > widest + 1; --k) slots[k] = slots[k - 1];
            slots[widest] = bvh_.nodes[opened].leftOrFirst;
            slots[widest + 1] = bvh_.nodes[opened].leftOrFirst + 1;
            ++used;
        }

        Aabb all;
        for (int k = 0; k < used; ++k) all.grow(boundsOf(bvh_.nodes[slots[k]]));
        AxisGrid grid[3];
        for (int axis = 0; axis < 3; ++axis) grid[axis] = gridOver(all.min[axis], all.max[axis]);
        uint32_t lower[3] = {}, upper[3] = {}, links[kWidth];
        for (int k = 0; k < kWidth; ++k) {
            links[k] = VKRT_WIDE_EMPTY;
            if (k >= used) continue;
            const gpu::BvhNode& child = bvh_.nodes[slots[k]];
            for (int axis = 0; axis < 3; ++axis) {
                lower[axis] |= quantizeLower(grid[axis], child.boundsMin[axis]) << (8 * k);
                upper[axis] |= quantizeUpper(grid[axis], child.boundsMax[axis]) << (8 * k);
            }
            if (child.primCount > 0) {
                if (child.primCount >= (VKRT_WIDE_EMPTY >> VKRT_WIDE_COUNT_SHIFT)) {
                    throw std::runtime_error("BVH leaf too large for the wide node's links");
                }
                if (child.leftOrFirst > VKRT_WIDE_INDEX_MASK) {
                    throw std::runtime_error("more primitives than the wide node's links index (2^" +
                                             std::to_string(std::countr_one(VKRT_WIDE_INDEX_MASK)) + ")");
                }
                links[k] = (child.primCount << VKRT_WIDE_COUNT_SHIFT) | child.leftOrFirst;
            } else {
                links[k] = emit(slots[k]);
                if (links[k] > VKRT_WIDE_INDEX_MASK) throw std::runtime_error("too many wide BVH nodes");
            }
        }
        gpu::WideBvhNode& node = nodes_[self];
        node.originX = grid[0].origin;
        node.originY = grid[1].origin;
        node.originZ = grid[2].origin;
        node.exponents = grid[0].exponent | (grid[1].exponent << 8) | (grid[2].exponent << 16);
        node.lowerX = lower[0];
        node.lowerY = lower[1];
        node.lowerZ = lower[2];
        node.upperX = upper[0];
        node.upperY = upper[1];
        node.upperZ = upper[2];
        node.child0 = links[0];
        node.child1 = links[1];
        node.child2 = links[2];
        node.child3 = links[3];
        return self;
    }

    std::vector<gpu::WideBvhNode> take() { return std::move(nodes_); }

  private:
    const FlatBvh& bvh_;
    std::vector<gpu::WideBvhNode> nodes_;
};

}  // namespace

std::vector<gpu::WideBvhNode> collapseToWide(const FlatBvh& bvh) {
    if (bvh.empty() || bvh.nodes.empty()) {
        gpu::WideBvhNode none{};
        none.child0 = none.child1 = none.child2 = none.child3 = VKRT_WIDE_EMPTY;
        return {none};
    }
    WideCollapse collapse(bvh);
    collapse.emit(0);
    return collapse.take();
}

uint32_t wideChildLink(const gpu::WideBvhNode& node, int slot) {
    const uint32_t links[kWidth] = {node.child0, node.child1, node.child2, node.child3};
    return links[slot];
}

Aabb wideChildBounds(const gpu::WideBvhNode& node, int slot) {
    if (wideChildLink(node, slot) == VKRT_WIDE_EMPTY) return Aabb{};
    const float origin[3] = {node.originX, node.originY, node.originZ};
    const uint32_t lower[3] = {node.lowerX, node.lowerY, node.lowerZ};
    const uint32_t upper[3] = {node.upperX, node.upperY, node.upperZ};
    Aabb box;
    for (int axis = 0; axis < 3; ++axis) {
        const uint32_t exponent = (node.exponents >> (8 * axis)) & 0xffu;
        box.min[axis] = decodeBound(origin[axis], byteOf(lower[axis], slot), exponent);
        box.max[axis] = decodeBound(origin[axis], byteOf(upper[axis], slot), exponent);
    }
    return box;
}

}  // namespace vkrt
