// Walking a flattened BVH on the CPU: near child first, with an explicit stack, as the GPU does.
// The primitive test is a callback, so the same walk serves closest-hit and shadow (any-hit) queries.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

#include "bvh/flat_bvh.h"

namespace vkrt {

template <typename Real>
struct RayT {
    glm::vec<3, Real> origin;
    glm::vec<3, Real> direction;
};

// Slab test (Kay and Kajiya). A zero direction component is handled explicitly, and the far distance is
// widened by a few ulps so that rounding never misses a box the ray touches (Ize, "Robust BVH Ray
// Traversal", 2013). Returns the entry distance, or infinity on a miss.
template <typename Real>
Real intersectBox(const gpu::BvhNode& node, const RayT<Real>& ray, const glm::vec<3, Real>& inverseDirection,
                  Real tMin, Real tMax) {
    Real tNear = tMin, tFar = tMax;
    for (int axis = 0; axis < 3; ++axis) {
        const Real lo = static_cast<Real>(node.boundsMin[axis]);
        const Real hi = static_cast<Real>(node.boundsMax[axis]);
        if (ray.direction[axis] == Real(0)) {
            if (ray.origin[axis] < lo || ray.origin[axis] > hi) return std::numeric_limits<Real>::infinity();
            continue;
        }
        Real t0 = (lo - ray.origin[axis]) * inverseDirection[axis];
        Real t1 = (hi - ray.origin[axis]) * inverseDirection[axis];
        if (t0 > t1) std::swap(t0, t1);
        constexpr Real widen = Real(1) + 4 * std::numeric_limits<Real>::epsilon();
        tNear = std::max(tNear, t0);
        tFar = std::min(tFar, t1 * widen);
        if (tNear > tFar) return std::numeric_limits<Real>::infinity();
    }
    return tNear;
}

// Calls `visit(prim, tMax)` for each primitive in a leaf whose box the ray enters before tMax. `visit` may
// shrink tMax (closest hit) and returns true to stop the walk (any hit).
template <typename Real, typename Visit>
void traverseBvh(const FlatBvh& bvh, const RayT<Real>& ray, Real tMin, Real& tMax, Visit&& visit) {
    if (bvh.empty()) return;
    const glm::vec<3, Real> inverseDirection = Real(1) / ray.direction;
    uint32_t stack[VKRT_BVH_MAX_DEPTH];
    int stackSize = 0;
    uint32_t current = 0;
    if (intersectBox(bvh.nodes[0], ray, inverseDirection, tMin, tMax) ==
        std::numeric_limits<Real>::infinity())
        return;
    while (true) {
        const gpu::BvhNode& node = bvh.nodes[current];
        if (node.primCount > 0) {
            for (uint32_t i = 0; i < node.primCount; ++i) {
                if (visit(bvh.primIndices[node.leftOrFirst + i], tMax)) return;
            }
        } else {
            // Enter the nearer child now; put the farther one on the stack.
            uint32_t near = node.leftOrFirst, far = node.leftOrFirst + 1;
            Real tNear = intersectBox(bvh.nodes[near], ray, inverseDirection, tMin, tMax);
            Real tFar = intersectBox(bvh.nodes[far], ray, inverseDirection, tMin, tMax);
            if (tFar < tNear) {
                std::swap(near, far);
                std::swap(tNear, tFar);
            }
            if (tNear != std::numeric_limits<Real>::infinity()) {
                if (tFar != std::numeric_limits<Real>::infinity()) stack[stackSize++] = far;
                current = near;
                continue;
            }
        }
        // Pop until a node that is still in front of the closest hit so far.
        bool found = false;
        while (stackSize > 0) {
            current = stack[--stackSize];
            if (intersectBox(bvh.nodes[current], ray, inverseDirection, tMin, tMax) !=
                std::numeric_limits<Real>::infinity()) {
                found = true;
                break;
            }
        }
        if (!found) return;
    }
}

}  // namespace vkrt
