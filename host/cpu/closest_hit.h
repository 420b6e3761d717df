// The nearest triangle along a ray in double precision: the reference renderer's visibility query, also
// the oracle that GPU traversal is tested against.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "bvh/bvh_traversal.h"
#include "cpu/triangle_intersection.h"

namespace vkrt {

inline constexpr uint32_t kNoTriangle = 0xffffffffu;

struct SurfaceHit {
    uint32_t triangle = kNoTriangle;
    double t = 0.0;
    double u = 0.0, v = 0.0;  // barycentric weights of v1 and v2
};

// The closest hit in (0, tMax) other than triangle `exclude`; false on a miss.
inline bool closestHit(const std::vector<Triangle>& triangles, const FlatBvh& bvh, const RayT<double>& ray,
                       double tMax, uint32_t exclude, SurfaceHit& hit) {
    bool found = false;
    traverseBvh(bvh, ray, 0.0, tMax, [&](uint32_t prim, double& closest) {
        TriangleHit candidate;
        if (prim != exclude &&
            intersectTriangle(triangles[prim], ray.origin, ray.direction, 0.0, closest, candidate)) {
            closest = candidate.t;
            hit = {prim, candidate.t, candidate.u, candidate.v};
            found = true;
        }
        return false;
    });
    return found;
}

}  // namespace vkrt
