// The GGX (Trowbridge-Reitz) microfacet distribution for glossy reflection and rough refraction: Walter et
// al., "Microfacet Models for Refraction through Rough Surfaces" (EGSR 2007), with Heitz's height-correlated
// masking-shadowing ("Understanding the Masking-Shadowing Function", JCGT 3(2), 2014) and visible-normal
// sampling ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018). Directions are in a local
// frame whose z axis is the shading normal.
#ifndef VKRT_MICROFACET_H
#define VKRT_MICROFACET_H

#include "shading_language.h"

// Roughness below this is a perfect mirror (glTF roughness 0); above it alpha = roughness^2, at least the
// square of this, so the distribution stays finite.
#define VKRT_MIRROR_ROUGHNESS 1e-3

VKRT_SHADING_BEGIN

VKRT_FN real ggxAlpha(real roughness) {
    return max(roughness * roughness, VKRT_MIRROR_ROUGHNESS * VKRT_MIRROR_ROUGHNESS);
}

// D(h) for the unit microfacet normal `h` about the unit normal `normal`: microfacet normals per unit solid angle
// and unit projected area.
VKRT_FN real ggxD(real3 normal, real3 h, real alpha) {
    const real cosH = dot(normal, h);
    if (cosH <= 0.0) return 0.0;
    // d = cos^2 (a2 - 1) + 1, as sin^2 + cos^2 a2: in single precision a2 - 1 rounds to -1 for a near-mirror
    // (a2 = 1e-12), and the textbook form cancels to 0 at cos = 1 (D infinite where it is 1 / (pi a2); seen on an
    // NVIDIA GPU). sin^2 is the cross product's, not (1 - cos)(1 + cos): a cosine within an ulp of 1 spans 3e-4
    // rad, where a lobe of alpha 1e-6 lives within a few 1e-6, so D came out 0 or its peak and near-mirror
    // metals rendered up to 9% dark on the GPU.
    const real3 c = cross(normal, h);
    const real a2 = alpha * alpha;
    const real d = dot(c, c) + cosH * cosH * a2;
    return a2 / (VKRT_PI * d * d);
}

// Smith's Lambda for a direction at cosine `cosTheta` from the normal.
VKRT_FN real ggxLambda(real cosTheta, real alpha) {
    const real c2 = cosTheta * cosTheta;
    if (c2 >= 1.0) return 0.0;
    const real tan2 = (1.0 - c2) / c2;
    return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

VKRT_FN real ggxG1(real cosTheta, real alpha) { return 1.0 / (1.0 + ggxLambda(cosTheta, alpha)); }

// Height-correlated masking and shadowing of the pair (viewer, light).
VKRT_FN real ggxG2(real cosOut, real cosIn, real alpha) {
    return 1.0 / (1.0 + ggxLambda(cosOut, alpha) + ggxLambda(cosIn, alpha));
}

// A microfacet normal visible from `toViewer` (local, z up), distributed as D_v(h) = G1 max(0, v.h) D / v.z.
VKRT_FN real3 sampleGgxVisibleNormal(real3 toViewer, real alpha, real u1, real u2) {
    // Stretch the view direction onto the hemisphere configuration.
    const real3 vh = normalize(real3(alpha * toViewer.x, alpha * toViewer.y, toViewer.z));
    const real lengthSquared = vh.x * vh.x + vh.y * vh.y;
    const real3 t1 = lengthSquared > 0.0 ? real3(-vh.y, vh.x, 0.0) / sqrt(lengthSquared) : real3(1.0, 0.0, 0.0);
    const real3 t2 = cross(vh, t1);
    // A point on the projected disk, warped towards the visible half.
    const real r = sqrt(u1), phi = 2.0 * VKRT_PI * u2;
    const real p1 = r * cos(phi);
    const real s = 0.5 * (1.0 + vh.z);
    const real p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * r * sin(phi);
    const real3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    // Unstretch.
    return normalize(real3(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

// Density of a reflected direction when its half vector h was drawn by sampleGgxVisibleNormal:
// D_v(h) / (4 v.h) = G1(v) D(h) / (4 v.z), with the viewer at cosine cosOut from `normal`.
VKRT_FN real ggxReflectionPdf(real cosOut, real3 normal, real3 h, real alpha) {
    if (cosOut <= 0.0) return 0.0;
    return ggxG1(cosOut, alpha) * ggxD(normal, h, alpha) / (4.0 * cosOut);
}

// A direction about the z axis with density cos(theta) / pi (a Lambertian lobe), from the stratified pair
// (u1, u2) by Shirley and Chiu's concentric map of the square onto the disk, which keeps strata compact.
VKRT_FN real3 sampleCosineHemisphere(real u1, real u2) {
    const real a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
    real r = 0.0, phi = 0.0;
    if (a != 0.0 || b != 0.0) {
        if (abs(a) > abs(b)) {
            r = a;
            phi = 0.25 * VKRT_PI * (b / a);
        } else {
            r = b;
            phi = 0.5 * VKRT_PI - 0.25 * VKRT_PI * (a / b);
        }
    }
    const real x = r * cos(phi), y = r * sin(phi);
    return real3(x, y, sqrt(max(0.0, 1.0 - x * x - y * y)));
}

VKRT_SHADING_END

#endif  // VKRT_MICROFACET_H
