// The environment light: an equirectangular radiance map around the scene, seen by rays that leave it and
// importance sampled for direct light (pbrt-v4, "Image Infinite Lights" and "Piecewise-Constant 2D
// Distributions"; docs/environment.md).
//
// Mapping. Blender Cycles' equirectangular convention seen through Blender's glTF importer (glTF (x, y, z)
// is Blender (x, -z, y)), so a Cycles render of the same glTF with the same map as its world texture means
// the same. For a unit direction d in the map's frame, with u across the image (0: left edge) and v down it
// (0: top row):
//     u = 0.5 + atan2(d.z, d.x) / (2 pi)       (+X at the centre column, -Z at u = 0.25, +Z at u = 0.75)
//     v = acos(d.y) / pi                        (the top row is the zenith, +Y; the bottom row the nadir)
// and back: theta = pi v, phi = 2 pi (u - 0.5), d = (sin theta cos phi, cos theta, sin theta sin phi).
// The map turns by `rotation` about +Y, right-handed (what was at +Z moves towards +X): a world direction
// is looked up at R_y(-rotation) d. Lookups are nearest-texel: the map is piecewise constant, which is
// exactly what the sampling distribution below assumes.
//
// Sampling. Texel (x, y) is drawn with probability proportional to its luminance, plus the same share for
// every texel, times sin(theta) at its row's centre (the solid angle its rows cover): the shared part draws a
// tenth of the samples by solid angle alone, whatever the map's range (a sky beside a sun a million times as
// bright is still sampled). First a row from the marginal distribution over rows, then a texel from that row's
// conditional distribution, each by inverting a cumulative table, and a uniform point inside the texel. The
// tables' cumulative probabilities are multiples of the random numbers' step, 2^-24 (random.h), with at least
// one step for every texel and row of positive weight: each texel is drawn with exactly the probability the
// tables state, on both devices alike. The density over the image is pdf_uv = W H p(row) p(texel | row), and per
// solid angle pdf_uv / (2 pi^2 sin theta), the Jacobian of the mapping above.
//
// The device provides (VKRT_DEVICE): environmentSize() (width, height), environmentRotation() (its cosine and
// sine), environmentTexel(i) (the
// radiance of texel i = y W + x, strength included), environmentRowCdf(y) (the marginal cumulative
// probability of rows 0..y, ending at 1) and environmentColumnCdf(i) (the cumulative probability of texels
// 0..x within row y, ending at 1). The tables are built on the host (host/scene/environment_map.cpp).
#ifndef VKRT_ENVIRONMENT_H
#define VKRT_ENVIRONMENT_H

#include "optics.h"
#include "random.h"
#include "shading_language.h"

VKRT_SHADING_BEGIN

// The map's size and rotation about +Y.
struct EnvironmentMapInfo {
    uint width;
    uint height;
    real cosRotation;
    real sinRotation;
};

// A direction drawn from the map, its radiance and its density per solid angle (0: unusable).
struct EnvironmentSample {
    real3 direction;
    real3 radiance;
    real pdf;
};

// R_y(angle) d, with cos and sin given; R_y(-angle) when `inverse`.
VKRT_FN real3 rotateAboutY(real3 d, real cosAngle, real sinAngle, bool inverse) {
    const real s = inverse ? -sinAngle : sinAngle;
    return real3(cosAngle * d.x + s * d.z, d.y, -s * d.x + cosAngle * d.z);
}

VKRT_DEVICE_TEMPLATE
VKRT_FN EnvironmentMapInfo environmentMapInfo(VKRT_DEVICE_PARAM_ONLY) {
    const uvec2 size = VKRT_DEVICE(environmentSize)();
    const real2 rotation = VKRT_DEVICE(environmentRotation)();
    EnvironmentMapInfo map;
    map.width = size.x;
    map.height = size.y;
    map.cosRotation = rotation.x;
    map.sinRotation = rotation.y;
    return map;
}

// A world direction's place (u, v) on the map, both in [0, 1].
VKRT_FN real2 environmentUv(VKRT_IN(EnvironmentMapInfo) map, real3 direction) {
    const real3 d = rotateAboutY(normalize(direction), map.cosRotation, map.sinRotation, true);
    // At the poles the longitude is undefined (and GLSL's atan(0, 0) too): u is 0.5 there.
    const real u = d.x == 0.0 && d.z == 0.0 ? 0.5 : 0.5 + atan(d.z, d.x) / (2.0 * VKRT_PI);
    const real v = acos(clamp(d.y, -1.0, 1.0)) / VKRT_PI;
    return real2(u, v);
}

// The world direction at (u, v) on the map.
VKRT_FN real3 environmentDirection(VKRT_IN(EnvironmentMapInfo) map, real2 uv) {
    const real theta = VKRT_PI * uv.y, phi = 2.0 * VKRT_PI * (uv.x - 0.5);
    const real sinTheta = sin(theta);
    const real3 d = real3(sinTheta * cos(phi), cos(theta), sinTheta * sin(phi));
    return rotateAboutY(d, map.cosRotation, map.sinRotation, false);
}

// The texel holding (u, v): nearest lookup, clamped to the image.
VKRT_FN uint environmentTexelAt(VKRT_IN(EnvironmentMapInfo) map, real2 uv) {
    const uint x = uint(clamp(int(floor(uv.x * real(map.width))), 0, int(map.width) - 1));
    const uint y = uint(clamp(int(floor(uv.y * real(map.height))), 0, int(map.height) - 1));
    return y * map.width + x;
}

// Radiance arriving from the environment along `direction` (towards the scene from there).
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 environmentRadiance(VKRT_DEVICE_PARAM real3 direction) {
    const EnvironmentMapInfo map = environmentMapInfo(VKRT_DEVICE_ARG_ONLY);
    return VKRT_DEVICE(environmentTexel)(environmentTexelAt(map, environmentUv(map, direction)));
}

// The probability of row y, and of texel i (= y W + x) within its row: differences of the cumulative tables,
// so sampling and density agree to the last bit.
VKRT_DEVICE_TEMPLATE
VKRT_FN real environmentRowProbability(VKRT_DEVICE_PARAM uint y) {
    return VKRT_DEVICE(environmentRowCdf)(y) - (y > 0u ? VKRT_DEVICE(environmentRowCdf)(y - 1u) : 0.0);
}

VKRT_DEVICE_TEMPLATE
VKRT_FN real environmentColumnProbability(VKRT_DEVICE_PARAM uint i, uint x) {
    return VKRT_DEVICE(environmentColumnCdf)(i) - (x > 0u ? VKRT_DEVICE(environmentColumnCdf)(i - 1u) : 0.0);
}

// The density per solid angle with which sampleEnvironment draws `direction`.
VKRT_DEVICE_TEMPLATE
VKRT_FN real environmentPdf(VKRT_DEVICE_PARAM real3 direction) {
    const EnvironmentMapInfo map = environmentMapInfo(VKRT_DEVICE_ARG_ONLY);
    const real2 uv = environmentUv(map, direction);
    const real sinTheta = sin(VKRT_PI * uv.y);
    if (!(sinTheta > 0.0)) return 0.0;
    const uint i = environmentTexelAt(map, uv);
    const uint y = i / map.width;
    const real pdfUv = real(map.width) * real(map.height) * environmentRowProbability(VKRT_DEVICE_ARG y) *
                       environmentColumnProbability(VKRT_DEVICE_ARG i, i - y * map.width);
    return pdfUv / (2.0 * VKRT_PI * VKRT_PI * sinTheta);
}

// A direction drawn from the map for the pair (u1, u2) in [0, 1)^2 (pbrt-v4, PiecewiseConstant2D::Sample), and
// (fine1, fine2) in [0, 1) below the random numbers' step (see the texel's point).
VKRT_DEVICE_TEMPLATE
VKRT_FN EnvironmentSample sampleEnvironment(VKRT_DEVICE_PARAM real u1, real u2, real fine1, real fine2) {
    const EnvironmentMapInfo map = environmentMapInfo(VKRT_DEVICE_ARG_ONLY);
    // Row: the first whose cumulative probability exceeds u1 (binary search of the marginal table).
    uint lo = 0u, hi = map.height - 1u;
    while (lo < hi) {
        const uint mid = (lo + hi) / 2u;
        if (VKRT_DEVICE(environmentRowCdf)(mid) > u1) hi = mid;
        else lo = mid + 1u;
    }
    const uint y = lo;
    const real rowBelow = y > 0u ? VKRT_DEVICE(environmentRowCdf)(y - 1u) : 0.0;
    const real rowProbability = VKRT_DEVICE(environmentRowCdf)(y) - rowBelow;
    // Texel within the row: the same search in the row's conditional table.
    const uint first = y * map.width;
    lo = 0u;
    hi = map.width - 1u;
    while (lo < hi) {
        const uint mid = (lo + hi) / 2u;
        if (VKRT_DEVICE(environmentColumnCdf)(first + mid) > u2) hi = mid;
        else lo = mid + 1u;
    }
    const uint x = lo;
    const real columnBelow = x > 0u ? VKRT_DEVICE(environmentColumnCdf)(first + x - 1u) : 0.0;
    const real columnProbability = VKRT_DEVICE(environmentColumnCdf)(first + x) - columnBelow;
    // Where inside the texel: the remainders of u1 and u2 in their intervals, which keeps stratification,
    // continued below the step by fine1 and fine2. (An interval of a few steps, a dim texel's beside a bright one,
    // held u's remainder at a few points of the texel: at its corner alone for one step, the pole itself in the
    // top row.) The differences are exact; the sum keeps the fine part's bits that the interval's count leaves.
    const real dv = clamp((u1 - rowBelow + fine1 * VKRT_RANDOM_STEP) / rowProbability, 0.0, 1.0);
    const real du = clamp((u2 - columnBelow + fine2 * VKRT_RANDOM_STEP) / columnProbability, 0.0, 1.0);
    const real2 uv = real2((real(x) + du) / real(map.width), (real(y) + dv) / real(map.height));
    EnvironmentSample s;
    s.direction = environmentDirection(map, uv);
    s.radiance = VKRT_DEVICE(environmentTexel)(first + x);
    const real sinTheta = sin(VKRT_PI * uv.y);
    const real pdfUv = real(map.width) * real(map.height) * rowProbability * columnProbability;
    s.pdf = sinTheta > 0.0 && rowProbability > 0.0 && columnProbability > 0.0
                ? pdfUv / (2.0 * VKRT_PI * VKRT_PI * sinTheta)
                : 0.0;
    return s;
}

VKRT_SHADING_END

#endif  // VKRT_ENVIRONMENT_H
