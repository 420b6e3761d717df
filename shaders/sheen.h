// KHR_materials_sheen: a layer of fibres over the material, the "Charlie" microfacet distribution with its
// fitted shadowing (Estevez and Kulla, "Production Friendly Microfacet Sheen BRDF", 2017), as the extension
// and the Khronos sample viewer have it. The layer
// reflects sheenColor x E of the light arriving at cosine mu (E: the layer's directional albedo, tabulated),
// and the material beneath is scaled by 1 - max(sheenColor) E(mu_view), as the Khronos sample viewer does.
#ifndef VKRT_SHEEN_H
#define VKRT_SHEEN_H

#include "shading_language.h"

// The directional albedo table: E at SIZE x SIZE points, cos(view) = (i / (SIZE - 1))^2 along rows (the
// entries close where E falls steeply, within a few degrees of grazing), sheen roughness = j / (SIZE - 1)
// down columns (entry j * SIZE + i), interpolated bilinearly in sqrt(cos(view)) and roughness.
#define VKRT_SHEEN_TABLE_SIZE 32
// Rougher than this the distribution is sharper than the table resolves (and than the extension's
// references show): the roughness is clamped to it.
#define VKRT_SHEEN_MIN_ROUGHNESS 0.07

VKRT_SHADING_BEGIN

VKRT_FN real sheenAlpha(real roughness) {
    const real r = max(roughness, VKRT_SHEEN_MIN_ROUGHNESS);
    return r * r;
}

// The Charlie distribution of microfibre normals at cosine cosH from the normal.
VKRT_FN real charlieD(real cosH, real alpha) {
    const real inverse = 1.0 / alpha;
    const real sin2 = max(1.0 - cosH * cosH, 0.0);
    return (2.0 + inverse) * pow(sin2, 0.5 * inverse) / (2.0 * VKRT_PI);
}

// Estevez and Kulla's fit of the Charlie distribution's log Lambda, in x = cos theta, for width alpha (their
// table 1: the coefficients blend between alpha = 0 and 1 by (1 - alpha)^2).
VKRT_FN real charlieLogLambdaFit(real x, real alpha) {
    const real t = (1.0 - alpha) * (1.0 - alpha);
    const real a = mix(21.5473, 25.3245, t), b = mix(3.82987, 3.32435, t), c = mix(0.19823, 0.16801, t);
    const real d = mix(-1.97760, -1.27393, t), e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

// Smith's Lambda of the Charlie distribution, fitted below cos theta = 0.5 and mirrored above it.
VKRT_FN real charlieLambda(real cosTheta, real alpha) {
    cosTheta = clamp(cosTheta, 0.0, 1.0);  // rounding can take a cosine just past 1 (pow of a negative)
    if (cosTheta < 0.5) return exp(charlieLogLambdaFit(cosTheta, alpha));
    return exp(2.0 * charlieLogLambdaFit(0.5, alpha) - charlieLogLambdaFit(1.0 - cosTheta, alpha));
}

// The visibility term G / (4 cos_i cos_o) with the Charlie distribution's height-correlated shadowing.
VKRT_FN real sheenVisibility(real cosIn, real cosOut, real alpha) {
    const real g = 1.0 / (1.0 + charlieLambda(cosOut, alpha) + charlieLambda(cosIn, alpha));
    return clamp(g / (4.0 * cosOut * cosIn), 0.0, 1.0);
}

// The sheen lobe per unit sheen colour, for light from `toLight` (0 below the surface).
VKRT_FN real sheenLobe(real3 normal, real3 toViewer, real3 toLight, real alpha) {
    const real cosOut = dot(normal, toViewer), cosIn = dot(normal, toLight);
    if (cosOut <= 0.0 || cosIn <= 0.0) return 0.0;
    return charlieD(dot(normal, normalize(toViewer + toLight)), alpha) * sheenVisibility(cosIn, cosOut, alpha);
}

// The lobe's directional albedo seen at cosine cosView (its integral times cos over the hemisphere of light
// directions), by the midpoint rule on `steps` x `steps` cells in (cos theta, phi in [0, pi]; the lobe is
// symmetric about the plane of the normal and the viewer): the table's entries.
VKRT_FN real sheenAlbedoIntegral(real cosView, real roughness, int steps) {
    const real cosV = max(cosView, 1e-4);
    const real3 normal = real3(0.0, 0.0, 1.0);
    const real3 toViewer = real3(sqrt(1.0 - cosV * cosV), 0.0, cosV);
    const real alpha = sheenAlpha(roughness);
    real sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        const real cosL = (real(i) + 0.5) / real(steps);
        const real sinL = sqrt(1.0 - cosL * cosL);
        for (int j = 0; j < steps; ++j) {
            const real phi = VKRT_PI * (real(j) + 0.5) / real(steps);
            const real3 toLight = real3(sinL * cos(phi), sinL * sin(phi), cosL);
            sum += sheenLobe(normal, toViewer, toLight, alpha) * cosL;
        }
    }
    // Each cell spans 1 / steps in cos theta and pi / steps in phi; the other half of the circle mirrors it.
    return 2.0 * sum * VKRT_PI / (real(steps) * real(steps));
}

#ifdef VKRT_HAS_SHEEN
// E(cosView, roughness) from the table the device holds (VKRT_DEVICE(sheenTable)(entry)).
VKRT_DEVICE_TEMPLATE
VKRT_FN real sheenAlbedo(VKRT_DEVICE_PARAM real cosView, real roughness) {
    const real last = real(VKRT_SHEEN_TABLE_SIZE - 1);
    const real x = sqrt(clamp(cosView, 0.0, 1.0)) * last, y = clamp(roughness, 0.0, 1.0) * last;
    const int i = min(int(x), VKRT_SHEEN_TABLE_SIZE - 2), j = min(int(y), VKRT_SHEEN_TABLE_SIZE - 2);
    const real fx = x - real(i), fy = y - real(j);
    const uint row = uint(j * VKRT_SHEEN_TABLE_SIZE + i);
    const uint size = uint(VKRT_SHEEN_TABLE_SIZE);
    return (1.0 - fy) * ((1.0 - fx) * real(VKRT_DEVICE(sheenTable)(row)) + fx * real(VKRT_DEVICE(sheenTable)(row + 1u))) +
           fy * ((1.0 - fx) * real(VKRT_DEVICE(sheenTable)(row + size)) +
                 fx * real(VKRT_DEVICE(sheenTable)(row + size + 1u)));
}
#endif

VKRT_SHADING_END

#endif  // VKRT_SHEEN_H
