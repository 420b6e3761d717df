// Analytic spheres (VKRT_sphere): the roots of a ray against a sphere in the numerically careful form of
// Haines, Guenther and Akenine-Moller, "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing
// Gems, ch. 7, 2019), and the sphere's texture coordinates.
#ifndef VKRT_SPHERE_GEOMETRY_H
#define VKRT_SPHERE_GEOMETRY_H

#include "shading_language.h"

// The precision of the root finding. The CPU reference works in double. On the GPU, VKRT_SPHERE_FLOAT64 (set
// when the device has shaderFloat64) does too: a float ray origin minus a float centre is exact in double, so
// a sphere a million times larger than the view (a planet as the ground) keeps the digits of its surface near
// the viewer; in float they round to the spacing of floats at the sphere's centre. Only scenes with spheres
// pay for it.
#if defined(__cplusplus) || defined(VKRT_SPHERE_FLOAT64)
#define VKRT_SPHERE_REAL double
#define VKRT_SPHERE_REAL3 dvec3
#else
#define VKRT_SPHERE_REAL float
#define VKRT_SPHERE_REAL3 vec3
#endif
#ifdef __cplusplus
namespace vkrt::shading {
using dvec3 = glm::dvec3;
}
#endif

VKRT_SHADING_BEGIN

// Both roots of |origin + t direction - centre| = radius, nearer first; false if the line misses. The
// discriminant comes from the centre's distance to the line (RTG eq. 7.5: no b^2 - 4ac cancellation), the
// near root from Vieta's formula (no -b + sqrt cancellation).
VKRT_FN bool sphereRoots(real3 center, real radius, real3 origin, real3 direction, VKRT_OUT(real) t0,
                         VKRT_OUT(real) t1) {
    const VKRT_SPHERE_REAL3 f = VKRT_SPHERE_REAL3(origin) - VKRT_SPHERE_REAL3(center);
    const VKRT_SPHERE_REAL3 d = VKRT_SPHERE_REAL3(direction);
    const VKRT_SPHERE_REAL r = VKRT_SPHERE_REAL(radius);
    const VKRT_SPHERE_REAL a = dot(d, d);
    const VKRT_SPHERE_REAL halfB = -dot(f, d);  // -b / 2
    const VKRT_SPHERE_REAL3 l = f + (halfB / a) * d;
    const VKRT_SPHERE_REAL discriminant = a * (r * r - dot(l, l));
    t0 = 0.0;
    t1 = 0.0;
    if (!(discriminant >= 0.0)) return false;
    const VKRT_SPHERE_REAL c = dot(f, f) - r * r;
    const VKRT_SPHERE_REAL q = halfB + (halfB < 0.0 ? -sqrt(discriminant) : sqrt(discriminant));
    t0 = q != 0.0 ? real(c / q) : 0.0;
    t1 = real(q / a);
    if (t0 > t1) {
        const real swap = t0;
        t0 = t1;
        t1 = swap;
    }
    return true;
}

// The nearest root in (tMin, tMax); false if there is none.
VKRT_FN bool intersectSphere(real3 center, real radius, real3 origin, real3 direction, real tMin, real tMax,
                             VKRT_OUT(real) t) {
    real t0, t1;
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

// Texture coordinates at outward unit normal n (+Y up, as in glTF): u is the longitude, 0.5 facing +Z; v runs
// from 0 at the north pole to 1 at the south pole. At the poles, where the longitude is undefined (and GLSL's
// atan(0, 0) too), u is 0.5.
VKRT_FN real2 sphereUv(real3 n) {
    const real u = n.x == 0.0 && n.z == 0.0 ? 0.5 : 0.5 + atan(n.x, n.z) / (2.0 * VKRT_PI);
    return real2(u, acos(clamp(n.y, -1.0, 1.0)) / VKRT_PI);
}

// The tangent frame of sphereUv at outward unit normal n, as a normal texture reads it (GpuTangents): the unit
// direction in which u grows in xyz, and in w the sign that turns w * cross(n, tangent) up the texture (the way
// v falls), which is +1 everywhere on the sphere. Zero at the poles, where u has no direction (the normal stays).
VKRT_FN real4 sphereTangent(real3 n) {
    const real3 along = real3(n.z, 0.0, -n.x);
    const real size = sqrt(along.x * along.x + along.z * along.z);
    return size > 0.0 ? real4(along / size, 1.0) : real4(0.0);
}

// 1 - cos(theta_max) of the cone a sphere subtends from a point at squared distance `distance2` from its
// centre, written as sin^2 / (1 + cos) to keep its digits for small, distant spheres.
VKRT_FN real coneOneMinusCos(real radius, real distance2) {
    const real sin2Max = radius * radius / distance2;
    return sin2Max / (1.0 + sqrt(max(0.0, 1.0 - sin2Max)));
}

VKRT_SHADING_END

#endif  // VKRT_SPHERE_GEOMETRY_H
