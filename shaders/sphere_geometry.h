// Analytic spheres (VKRT_sphere): the roots of a ray against a sphere in the numerically careful form of
// Haines, Guenther and Akenine-Moller, "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing
// Gems, ch. 7, 2019), and the sphere's texture coordinates.
#ifndef VKRT_SPHERE_GEOMETRY_H
#define VKRT_SPHERE_GEOMETRY_H

#include "shading_language.h"

// The precision of the root finding. The CPU reference works in double. On the GPU, VKRT_SPHERE_FLOAT64 (set
// where the device has shaderFloat64 and the scene a sphere 1024 times as wide as its typical primitive,
// host/gpu/scene_features.cpp) does too: a float ray origin minus a float centre is exact in double, so a
// sphere a million times larger than the view (a planet as the ground) keeps the digits of its surface near
// the viewer; in float they round to the spacing of floats at the sphere's centre. In float a root is off by
// about float epsilon times the distance from the ray's origin to the centre, which for smaller spheres is
// about what a triangle's test gives at the same distance.
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

// The tangent frame a normal texture reads (GpuTangents) on an analytic surface whose dP/du and dP/dv are
// `dpdu` and `dpdv` (both to one positive factor), under a texture transform whose linear part has rows `row0`
// and `row1` (KHR_texture_transform takes (u, v) to (row0 . (u, v), row1 . (u, v)) plus its offset): the frame
// of the transformed coordinates, whose derivatives are [dP/du dP/dv] R^-1, as host/scene/tangent_frames.cpp's
// orthogonalFrame makes it for meshes. In xyz the unit direction in which u' grows, made orthogonal to the unit
// `normal`; in w the sign that turns w * cross(normal, tangent) up the texture (the way v' falls). Zero where u'
// has no direction (the normal then stays), or where the transform collapses the texture.
VKRT_FN real4 texturedTangent(real3 normal, real3 dpdu, real3 dpdv, real2 row0, real2 row1) {
    const real determinant = row0.x * row1.y - row0.y * row1.x;
    // Both derivatives scaled alike before they are combined (a shape's scale can be beyond what a product keeps
    // in single precision), by |det R| / det R to keep R^-1's orientation.
    const real largest = max(max(abs(dpdu.x), max(abs(dpdu.y), abs(dpdu.z))),
                             max(abs(dpdv.x), max(abs(dpdv.y), abs(dpdv.z))));
    if (!(abs(determinant) > 0.0) || !(largest > 0.0)) return real4(0.0);
    const real scale = (determinant > 0.0 ? 1.0 : -1.0) / largest;
    dpdu *= scale;
    dpdv *= scale;
    real3 along = row1.y * dpdu - row1.x * dpdv;
    const real3 down = row0.x * dpdv - row0.y * dpdu;
    // Divided by its largest component before anything is squared.
    const real alongLargest = max(abs(along.x), max(abs(along.y), abs(along.z)));
    if (!(alongLargest > 0.0)) return real4(0.0);
    along /= alongLargest;
    const real3 tangent = along - normal * dot(normal, along);
    const real size = sqrt(dot(tangent, tangent));
    if (!(size > 1e-6)) return real4(0.0);
    return real4(tangent / size, dot(cross(normal, tangent), down) > 0.0 ? -1.0 : 1.0);
}

// dP/du and dP/dv of sphereUv on the unit sphere at p (|p| = 1), to one positive factor: u is the longitude over
// 2 pi, v the polar angle over pi.
VKRT_FN void sphereDerivatives(real3 p, VKRT_OUT(real3) dpdu, VKRT_OUT(real3) dpdv) {
    const real ring = sqrt(p.x * p.x + p.z * p.z);  // the sine of the polar angle
    dpdu = 2.0 * ring * real3(p.z, 0.0, -p.x);
    dpdv = real3(p.y * p.x, -(p.x * p.x + p.z * p.z), p.y * p.z);
}

// The tangent frame of sphereUv at outward unit normal n under a texture transform's rows (texturedTangent).
// Untransformed, the tangent points east and w is +1 everywhere. Zero at the poles, where u has no direction.
VKRT_FN real4 sphereTangent(real3 n, real2 row0, real2 row1) {
    real3 dpdu, dpdv;
    sphereDerivatives(n, dpdu, dpdv);
    return texturedTangent(n, dpdu, dpdv, row0, row1);
}

// 1 - cos(theta_max) of the cone a sphere subtends from a point at squared distance `distance2` from its
// centre, written as sin^2 / (1 + cos) to keep its digits for small, distant spheres.
VKRT_FN real coneOneMinusCos(real radius, real distance2) {
    const real sin2Max = radius * radius / distance2;
    return sin2Max / (1.0 + sqrt(max(0.0, 1.0 - sin2Max)));
}

VKRT_SHADING_END

#endif  // VKRT_SPHERE_GEOMETRY_H
