// Rays in single precision, and spawning new rays off a surface without hitting it again. The CPU reference
// keeps its own, double-precision choices (host/cpu/reference_renderer.cpp, host/cpu/cpu_shading_device.h).
#ifndef VKRT_RAY_GLSL
#define VKRT_RAY_GLSL

#include "optics.h"

struct Ray {
    vec3 origin;
    vec3 direction;
};

// A hit point and the size of the numbers it was computed from. Rounding errors of the point, and of
// the intersection test that found it, are a small multiple of float epsilon times that magnitude.
struct SurfacePoint {
    vec3 position;
    float errorScale;
};

// The hit point, computed whichever way rounds less: from the barycentrics (error relative to the
// vertices' magnitude) or along the ray (error relative to |origin| + t). Huge triangles seen from nearby
// favour the ray; distant hits favour the barycentrics.
//
// Along the ray, the distance t is the watertight test's, computed from the corners relative to the origin in
// float: off by about float epsilon times the corners' distance, which a huge triangle seen from nearby makes
// far more than the point's own rounding (a unit sphere on a ground quad 2e5 across lost its contact shadows
// in 0.7% of the pixels). With VKRT_TRIANGLE_FLOAT64 (a scene with large triangles, scene_features.cpp, on a
// device with shaderFloat64) the distance to the triangle's plane is then computed again in double, where
// float corners, origin and direction are exact and the plane's normal nearly so.
SurfacePoint hitPoint(vec3 origin, vec3 direction, float t, vec3 v0, vec3 v1, vec3 v2, float u, float v) {
    const float vertexScale = max(maxAbs(v0), max(maxAbs(v1), maxAbs(v2)));
    const float rayScale = maxAbs(origin) + t;
    if (rayScale < vertexScale) {
#ifdef VKRT_TRIANGLE_FLOAT64
        const dvec3 corner = dvec3(v0);
        const dvec3 normal = cross(dvec3(v1) - corner, dvec3(v2) - corner);
        const float planeT = float(dot(normal, corner - dvec3(origin)) / dot(normal, dvec3(direction)));
        if (planeT > 0.0 && planeT < VKRT_INFINITY) t = planeT;
#endif
        return SurfacePoint(origin + t * direction, maxAbs(origin) + t);
    }
    return SurfacePoint(barycentric(v0, v1, v2, vec2(u, v)), vertexScale);
}

// A sphere's hit point, and the outward normal there. Projected onto the sphere (RTG ch. 7) when that rounds
// less than the point along the ray; a sphere much larger than the distance travelled (the ground) keeps the
// ray's point, whose error is relative to |origin| + t rather than to the sphere's far-away centre. Roots found
// in float (sphere_geometry.h) are off by about float epsilon times the distance from the origin to the centre,
// which is far more than |origin| + t for a ray from near the world's origin to a sphere there (a glass ball
// resting on a mirror at the origin: rays reflected at the contact and refracted into the ball met its surface
// again at once, offset by |origin| + t alone), so the point's error scale takes that distance too.
SurfacePoint sphereHitPoint(vec3 origin, vec3 direction, float t, vec3 center, float radius, out vec3 normal) {
    const vec3 alongRay = origin + t * direction;
    normal = normalize(alongRay - center);
#ifdef VKRT_SPHERE_FLOAT64
    const float rayScale = maxAbs(origin) + t;
#else
    const float rayScale = maxAbs(origin) + t + maxAbs(origin - center);
#endif
    const float sphereScale = maxAbs(center) + radius;
    if (rayScale < sphereScale) return SurfacePoint(alongRay, rayScale);
    return SurfacePoint(center + radius * normal, sphereScale);
}

// Moves a point off a surface along the geometric normal `n` (pointing to the side the new ray leaves
// from) by shared.h's VKRT_RAY_OFFSET_EPSILON of its error scale, so the new ray cannot start behind the
// surface. The offset scales with the scene, so tiny and huge scenes behave alike (a fixed absolute offset
// near the origin, as in Ray Tracing Gems ch. 6, breaks scenes a few microns across). The primitive just left
// is also excluded from the new ray's hits.
vec3 offsetRayOrigin(vec3 position, float errorScale, vec3 n) {
    return position + (max(errorScale, maxAbs(position)) * float(VKRT_RAY_OFFSET_EPSILON)) * n;
}

#endif
