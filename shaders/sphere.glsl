// Analytic spheres (VKRT_sphere), in single precision as in Haines, Guenther and Akenine-Moller,
// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7, 2019); the CPU reference
// (host/cpu/sphere_intersection.h, area_lights.cpp) does the same in double.
#ifndef VKRT_SPHERE_GLSL
#define VKRT_SPHERE_GLSL

// With VKRT_SPHERE_FLOAT64 (when the device has shaderFloat64) the test runs in double precision: a float
// ray origin minus a float centre is exact in double, so a sphere a million times larger than the view
// (a planet as the ground) keeps the digits of its surface near the viewer; in float they round to the
// spacing of floats at the sphere's centre. Only scenes with spheres pay for it.
#ifdef VKRT_SPHERE_FLOAT64
#define SphereReal double
#define SphereVec dvec3
#else
#define SphereReal float
#define SphereVec vec3
#endif

// Both roots of |origin + t direction - centre| = radius, nearer first; false if the line misses. The
// discriminant comes from the centre's distance to the line (no b^2 - 4ac cancellation), the near root from
// Vieta's formula (no -b + sqrt cancellation).
bool sphereRoots(vec3 center, float radius, vec3 origin, vec3 direction, out float t0, out float t1) {
    const SphereVec f = SphereVec(origin) - SphereVec(center);
    const SphereVec d = SphereVec(direction);
    const SphereReal r = SphereReal(radius);
    const SphereReal a = dot(d, d);
    const SphereReal halfB = -dot(f, d);
    const SphereVec l = f + (halfB / a) * d;
    const SphereReal discriminant = a * (r * r - dot(l, l));
    t0 = 0.0;
    t1 = 0.0;
    if (!(discriminant >= 0.0)) return false;
    const SphereReal c = dot(f, f) - r * r;
    const SphereReal q = halfB + (halfB < 0.0 ? -sqrt(discriminant) : sqrt(discriminant));
    t0 = q != 0.0 ? float(c / q) : 0.0;
    t1 = float(q / a);
    if (t0 > t1) {
        const float swap = t0;
        t0 = t1;
        t1 = swap;
    }
    return true;
}

bool intersectSphere(vec3 center, float radius, vec3 origin, vec3 direction, float tMin, float tMax, out float t) {
    float t0, t1;
    t = 0.0;
    if (!sphereRoots(center, radius, origin, direction, t0, t1)) return false;
    if (t0 > tMin && t0 < tMax) {
        t = t0;
        return true;
    }
    if (t1 > tMin && t1 < tMax) {
        t = t1;
        return true;
    }
    return false;
}

// The hit point, and the outward normal there. Projected onto the sphere (RTG ch. 7) when that rounds less
// than the point along the ray; a sphere much larger than the distance travelled (the ground) keeps the
// ray's point, whose error is relative to |origin| + t rather than to the sphere's far-away centre.
SurfacePoint sphereHitPoint(vec3 origin, vec3 direction, float t, vec3 center, float radius, out vec3 normal) {
    const vec3 alongRay = origin + t * direction;
    normal = normalize(alongRay - center);
    const float rayScale = maxAbs(origin) + t;
    const float sphereScale = maxAbs(center) + radius;
    if (rayScale < sphereScale) return SurfacePoint(alongRay, rayScale);
    return SurfacePoint(center + radius * normal, sphereScale);
}

// Texture coordinates at outward unit normal n: u the longitude (0.5 facing +Z), v from 0 at the north
// (+Y) pole to 1 at the south pole.
vec2 sphereUv(vec3 n) {
    return vec2(0.5 + atan(n.x, n.z) / (2.0 * 3.14159265358979323846), acos(clamp(n.y, -1.0, 1.0)) / 3.14159265358979323846);
}

#endif
