// The nearest primitive (triangle or sphere) along a ray in double precision: the reference renderer's
// visibility query, also the oracle that GPU traversal is tested against.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "bvh/bvh_traversal.h"
#include "cpu/solid_intersection.h"
#include "cpu/triangle_intersection.h"
#include "scene/scene.h"
#include "shared.h"
#include "sphere_geometry.h"

namespace vkrt {

inline constexpr uint32_t kNoPrimitive = VKRT_NO_PRIMITIVE;

struct SurfaceHit {
    uint32_t primitive = kNoPrimitive;  // a triangle, a sphere (Scene::isSphere) or a solid (Scene::isSolid)
    double t = 0.0;
    // Triangles: barycentric weights of v1 and v2; spheres: unused; solids: the shape and face crossed
    // (encodeCrossing).
    double u = 0.0, v = 0.0;
};

// The nearest hit on one primitive, where it is at shutter time `time`, in (tMin, tMax).
inline bool intersectPrimitive(const Scene& scene, uint32_t primitive, const RayT<double>& ray, double tMin,
                               double tMax, TriangleHit& hit, double time = 0.0) {
    if (scene.isSolid(primitive)) {
        SolidIntervals intervals =
            solidIntervals(scene, scene.solidOf(primitive), ray.origin, ray.direction, time);
        shading::CsgCrossing crossing;
        if (!solidCrossing(intervals, tMin, tMax, crossing)) return false;
        hit.t = crossing.t;
        encodeCrossing(scene.solidOf(primitive), crossing, hit.u, hit.v);
        return true;
    }
    if (!scene.isSphere(primitive)) {
        return intersectTriangle(scene.triangleAt(primitive, time), ray.origin, ray.direction, tMin, tMax,
                                 hit);
    }
    hit.u = hit.v = 0.0;
    const Sphere sphere = scene.sphereAt(primitive, time);
    return shading::intersectSphere(glm::dvec3(sphere.center), sphere.radius, ray.origin, ray.direction, tMin,
                                    tMax, hit.t);
}

// The width of a tie (VKRT_TIE_EPSILON) at distance t along a ray whose origin's largest coordinate is
// `originScale`: relative to the magnitude of the numbers the distance came from, as the GPU's rounding is
// (traverse.glsl's tieWidth).
inline double tieWidth(double t, double originScale) {
    return VKRT_TIE_EPSILON * (originScale + t);
}

// Whether a hit at `t` on primitive `index` wins over the best so far: nearer by more than a tie's width, or
// a tie with a smaller index.
inline bool winsOver(double t, uint32_t index, double bestT, uint32_t bestIndex, double originScale) {
    const double tolerance = tieWidth(bestT, originScale);
    return t < bestT - tolerance || (t <= bestT + tolerance && index < bestIndex);
}

// The closest hit in (tMin, tMax) other than primitive `exclude`, ties broken by primitive index, with the
// scene at shutter time `time`; false on a miss.
inline bool closestHitBeyond(const Scene& scene, const FlatBvh& bvh, const RayT<double>& ray, double tMin,
                             double tMax, uint32_t exclude, SurfaceHit& hit, double time = 0.0) {
    bool found = false;
    const double originScale =
        std::max({std::abs(ray.origin.x), std::abs(ray.origin.y), std::abs(ray.origin.z)});
    traverseBvh(bvh, ray, tMin, tMax, [&](uint32_t prim, double& limit) {
        TriangleHit candidate;
        if (prim != exclude && intersectPrimitive(scene, prim, ray, tMin, limit, candidate, time) &&
            (!found || winsOver(candidate.t, prim, hit.t, hit.primitive, originScale))) {
            hit = {prim, candidate.t, candidate.u, candidate.v};
            found = true;
            // Keep looking a tie's width beyond the best hit, where a tie can still win.
            limit = std::min(tMax, hit.t + tieWidth(hit.t, originScale));
        }
        return false;
    });
    return found;
}

// The same in (0, tMax).
inline bool closestHit(const Scene& scene, const FlatBvh& bvh, const RayT<double>& ray, double tMax,
                       uint32_t exclude, SurfaceHit& hit, double time = 0.0) {
    return closestHitBeyond(scene, bvh, ray, 0.0, tMax, exclude, hit, time);
}

}  // namespace vkrt
