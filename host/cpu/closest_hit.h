// The nearest primitive (triangle, sphere or solid) along a ray in double precision: the reference renderer's
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
#include "ties.h"

namespace vkrt {

inline constexpr uint32_t kNoPrimitive = VKRT_NO_PRIMITIVE;

struct SurfaceHit {
    uint32_t primitive = kNoPrimitive;  // a triangle, a sphere (Scene::isSphere) or a solid (Scene::isSolid)
    double t = 0.0;
    // Triangles: barycentric weights of v1 and v2; spheres: unused; solids: the shape and face crossed
    // (encodeCrossing).
    double u = 0.0, v = 0.0;
    // Where a search for what lies beyond starts: a solid's crossing is crossed with the coincident faces of
    // its other shapes, up to its tie group's end (shape_geometry.h's csgCrossing); else t.
    double groupEnd = 0.0;
};

// The nearest hit on one primitive, where it is at shutter time `time`, in (tMin, tMax), and where a search
// beyond it starts (SurfaceHit::groupEnd).
inline bool intersectPrimitive(const Scene& scene, uint32_t primitive, const RayT<double>& ray, double tMin,
                               double tMax, TriangleHit& hit, double time, double& groupEnd) {
    if (scene.isSolid(primitive)) {
        SolidIntervals intervals =
            solidIntervals(scene, scene.solidOf(primitive), ray.origin, ray.direction, time);
        shading::CsgCrossing crossing;
        if (!solidCrossing(intervals, tMin, tMax, crossing)) return false;
        hit.t = crossing.t;
        groupEnd = crossing.groupEnd;
        encodeCrossing(scene.solidOf(primitive), crossing, hit.u, hit.v);
        return true;
    }
    bool found;
    if (!scene.isSphere(primitive)) {
        found =
            intersectTriangle(scene.triangleAt(primitive, time), ray.origin, ray.direction, tMin, tMax, hit);
    } else {
        hit.u = hit.v = 0.0;
        const Sphere sphere = scene.sphereAt(primitive, time);
        found = shading::intersectSphere(glm::dvec3(sphere.center), sphere.radius, ray.origin, ray.direction,
                                         tMin, tMax, hit.t);
    }
    groupEnd = hit.t;
    return found;
}

// The closest hit before tMax past where `walk` stands (shading::WalkPast: beyond tMin, before any hit was
// passed) other than primitives `exclude` and `alsoExclude`, with the scene at shutter time `time`; false on
// a miss. Solids are never skipped (a CSG object need not be convex), as on the GPU (traverse.glsl). Ties are
// won by the smallest primitive index within a tie's width of the nearest hit (ties.h, the GPU's rule too),
// whatever order the walk meets them in: a walk that lost a candidate runs once more. `nearest` is the
// nearest hit's distance, which starts its tie group (ties.h's walkPast).
inline bool closestHitPast(const Scene& scene, const FlatBvh& bvh, const RayT<double>& ray,
                           const shading::WalkPast& past, double tMax, uint32_t exclude, SurfaceHit& hit,
                           double& nearest, double time = 0.0, uint32_t alsoExclude = kNoPrimitive) {
    const double originScale =
        std::max({std::abs(ray.origin.x), std::abs(ray.origin.y), std::abs(ray.origin.z)});
    nearest = tMax;
    double searchLimit = tMax;
    bool found = false, lost = false;
    auto walk = [&] {
        // Boxes: no hit not yet passed lies before the current group's start.
        traverseBvh(bvh, ray, past.start, searchLimit, [&](uint32_t prim, double& limit) {
            TriangleHit candidate;
            double groupEnd;
            if ((prim == exclude || prim == alsoExclude) && !scene.isSolid(prim)) return false;
            if (!intersectPrimitive(scene, prim, ray, shading::searchFloor(past, prim), limit, candidate,
                                    time, groupEnd))
                return false;
            const double ranked = shading::rankedDistance(past, candidate.t);
            if (shading::takesClosestHit(ranked, prim, found, shading::rankedDistance(past, hit.t),
                                         hit.primitive, originScale, nearest, lost))
                hit = {prim, candidate.t, candidate.u, candidate.v, groupEnd};
            found = true;
            // Keep looking a tie's width beyond the nearest hit, where a tie can still win, and over the rest
            // of the current group.
            limit = std::min(limit, std::max(nearest + shading::tieWidth(nearest, originScale), past.end));
            return false;
        });
    };
    walk();
    if (lost) {
        found = false;
        walk();
    }
    return found;
}

// The closest hit in (tMin, tMax) other than primitives `exclude` and `alsoExclude`, with the scene at
// shutter time `time`; false on a miss (closestHitPast, before any hit was passed).
inline bool closestHitBeyond(const Scene& scene, const FlatBvh& bvh, const RayT<double>& ray, double tMin,
                             double tMax, uint32_t exclude, SurfaceHit& hit, double time = 0.0,
                             uint32_t alsoExclude = kNoPrimitive) {
    double nearest;
    return closestHitPast(scene, bvh, ray, shading::walkPastFrom(tMin), tMax, exclude, hit, nearest, time,
                          alsoExclude);
}

// The same in (0, tMax).
inline bool closestHit(const Scene& scene, const FlatBvh& bvh, const RayT<double>& ray, double tMax,
                       uint32_t exclude, SurfaceHit& hit, double time = 0.0) {
    return closestHitBeyond(scene, bvh, ray, 0.0, tMax, exclude, hit, time);
}

}  // namespace vkrt
