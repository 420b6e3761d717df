// Emissive triangles and spheres as area lights. The device picks one in proportion to its power (the table
// lives with the scene, host/scene/light_table.h); these functions then choose a point on it and give the
// densities that multiple importance sampling weighs. A triangle is sampled uniformly by area; a sphere by
// solid angle, uniformly inside the cone it subtends from the shading point (uniformly by area when the point
// is inside it).
#ifndef VKRT_AREA_LIGHT_H
#define VKRT_AREA_LIGHT_H

#include "optics.h"
#include "shading_language.h"
#include "sphere_geometry.h"

VKRT_SHADING_BEGIN

// A point on an emissive primitive.
struct LightPoint {
    uint primitive;
    real3 position;
    real3 normal;  // the emitting (front, outward) side
    real2 uv;      // barycentric weights of v1 and v2 (triangles) or texture coordinates (spheres)
    real pdfArea;  // per unit area, the choice of the light included
};

// A light's power, by which light sampling picks it: luminance times area (at the shutter's opening).
VKRT_FN real lightPower(real3 emission, real area) { return area * max(luminance(emission), 1e-12); }

VKRT_FN real triangleArea(real3 v0, real3 v1, real3 v2) { return 0.5 * length(cross(v1 - v0, v2 - v0)); }

// A uniform point on a triangle (Shirley and Chiu's square-root mapping); `pdfArea` is the light's pick
// probability over its area.
VKRT_FN LightPoint sampleTriangleLight(uint primitive, real3 v0, real3 v1, real3 v2, real pdfArea, real u, real v) {
    LightPoint p;
    p.primitive = primitive;
    const real root = sqrt(u);
    p.uv = real2(root * (1.0 - v), root * v);
    p.position = (1.0 - root) * v0 + p.uv.x * v1 + p.uv.y * v2;
    p.normal = normalize(cross(v1 - v0, v2 - v0));
    p.pdfArea = pdfArea;
    return p;
}

// A point of a sphere picked with probability `pick`, uniform in the cone of directions it subtends from
// `from` (pbrt-v4, Sphere::Sample), or uniform by area when `from` is inside.
VKRT_FN LightPoint sampleSphereLight(uint primitive, real3 center, real radius, real pick, real3 from, real u,
                                     real v) {
    LightPoint p;
    p.primitive = primitive;
    const real3 toCenter = center - from;
    const real distance2 = dot(toCenter, toCenter);
    const real phi = 2.0 * VKRT_PI * v;
    real oneMinusCosMax = 0.0;
    if (distance2 <= radius * radius) {
        const real z = 1.0 - 2.0 * u, ring = sqrt(max(0.0, 1.0 - z * z));
        p.normal = real3(ring * cos(phi), ring * sin(phi), z);
        p.pdfArea = pick / (4.0 * VKRT_PI * radius * radius);
    } else {
        const real3 axis = toCenter / sqrt(distance2);
        const real sin2Max = radius * radius / distance2;
        const real sinMax = sqrt(sin2Max);
        oneMinusCosMax = coneOneMinusCos(radius, distance2);
        const real oneMinusCos = u * oneMinusCosMax;
        const real cosTheta = 1.0 - oneMinusCos;
        const real sin2Theta = oneMinusCos * (2.0 - oneMinusCos);
        // The angle at the centre between the axis (reversed) and the sampled point.
        const real cosAlpha = sin2Theta / sinMax + cosTheta * sqrt(max(0.0, 1.0 - sin2Theta / sin2Max));
        const real sinAlpha = sqrt(max(0.0, 1.0 - cosAlpha * cosAlpha));
        real3 b1, b2;
        orthonormalBasis(axis, b1, b2);
        p.normal = -(sinAlpha * cos(phi) * b1 + sinAlpha * sin(phi) * b2 + cosAlpha * axis);
        p.pdfArea = 0.0;
    }
    p.position = center + radius * p.normal;
    p.uv = sphereUv(p.normal);
    if (oneMinusCosMax > 0.0) {
        // The cone's solid-angle density 1 / (2 pi (1 - cos theta_max)), per unit area at the point.
        const real3 offset = p.position - from;
        const real d2 = dot(offset, offset);
        const real cosLight = max(0.0, -dot(p.normal, offset) / sqrt(d2));
        p.pdfArea = pick * cosLight / (2.0 * VKRT_PI * oneMinusCosMax * d2);
    }
    return p;
}

// The density per unit solid angle, seen from a point at squared distance `distance2`, of a light point
// sampled with density `pdfArea` per unit area whose normal makes cosine `cosLight` with the direction back.
VKRT_FN real solidAnglePdfFromArea(real pdfArea, real distance2, real cosLight) {
    return cosLight > 0.0 ? pdfArea * distance2 / cosLight : 0.0;
}

// The density per unit solid angle with which sampleSphereLight, seen from `from`, picks a point at squared
// distance `distance2` and cosine `cosLight` on a sphere picked with probability `pick`.
VKRT_FN real sphereLightSolidAnglePdf(real3 center, real radius, real pick, real3 from, real distance2,
                                      real cosLight) {
    if (!(cosLight > 0.0)) return 0.0;
    const real3 toCenter = center - from;
    const real centerDistance2 = dot(toCenter, toCenter);
    if (centerDistance2 > radius * radius) return pick / (2.0 * VKRT_PI * coneOneMinusCos(radius, centerDistance2));
    return pick / (4.0 * VKRT_PI * radius * radius) * distance2 / cosLight;
}

VKRT_SHADING_END

#endif  // VKRT_AREA_LIGHT_H
