// Energy compensation for single-scattering GGX: a microfacet lobe that scatters light once loses what would
// scatter between microfacets again (about 60% for a white metal at roughness 1). Following Turquin,
// "Practical multiple scattering compensation for microfacet models" (2019), the lobe is scaled, for a viewer
// at cosine mu, by
// - a conductor's (and an opaque dielectric's) reflection: 1 + F0 (1 - E(mu)) / E(mu), with E the directional
//   albedo of the lobe with F = 1 and F0 the reflectance at normal incidence;
// - a refracting dielectric's reflection and transmission alike: 1 / E_eta(mu), with E_eta the albedo of both
//   together with the exact Fresnel term at relative index eta (Turquin's treatment of dielectrics);
// - the clear coat's lobe: 1 / E(mu), since its Fresnel term is taken at the viewer, outside the integral.
// Both albedos are integrated once on the host (host/scene/ggx_albedo_tables.cpp) and read by both renderers
// through VKRT_DEVICE, like the sheen's. docs/materials.md lists what is compensated and what remains.
#ifndef VKRT_ENERGY_COMPENSATION_H
#define VKRT_ENERGY_COMPENSATION_H

#include "microfacet.h"
#include "optics.h"
#include "shading_language.h"

// The conductor table: E at SIZE x SIZE points, sqrt(cos(view)) = i / (SIZE - 1) along rows (the square root
// spends entries near grazing, where E changes fastest), roughness = j / (SIZE - 1) down columns (entry
// j * SIZE + i), interpolated bilinearly.
#define VKRT_GGX_ALBEDO_SIZE 32
// The dielectric table: E_eta at COS x ROUGHNESS x ETA points, entry (k * ROUGHNESS + j) * COS + i, with cos
// and roughness as in the conductor table and eta at coordinate k / (ETA - 1) (ggxDielectricEtaCoordinate):
// every index from 0 to infinity (the ends: 1e-6 and 1e6, where all light is reflected), both ways across an
// interface alike, closest together around eta = 1, where E_eta changes fastest (total internal reflection
// sets in just below it), with eta = 1 on the middle entry.
// Interpolated trilinearly; its hemispherical averages (what a furnace shows) are within 0.5% of the integral
// (tests/gpu_energy_test.cpp checks points between entries).
#define VKRT_GGX_DIELECTRIC_COS_SIZE 16
#define VKRT_GGX_DIELECTRIC_ROUGHNESS_SIZE 16
#define VKRT_GGX_DIELECTRIC_ETA_SIZE 33

VKRT_SHADING_BEGIN

// The expected weight of a continuation the renderers draw for a viewer at cosine cosView from a GGX lobe of
// width ggxAlpha(roughness): the reflection through a visible normal, F G2 / G1 where it leaves above the
// surface, and, when `eta` > 0 (the relative index across the interface), the refraction through the same
// normal, (1 - F) G2 / G1 where it leaves below; F is the dielectric's Fresnel term, or 1 for eta = 0 (the
// conductor table). By the midpoint rule on `steps` x `steps` cells of the visible normal's random pair (u1,
// u2), with u1 = 1 - (1 - w)^2 for w uniform: the cells crowd where u1 nears 1, the steep microfacets that
// send light below the horizon, which a uniform grid misses at low roughness. The lobe is symmetric about the
// plane of the normal and the viewer, so u2 covers the half of the azimuths on one side of it (`steps` even).
VKRT_FN real ggxAlbedoIntegral(real cosView, real roughness, real eta, int steps) {
    const real cosV = clamp(cosView, 1e-4, 1.0);
    const real3 toViewer = real3(sqrt(1.0 - cosV * cosV), 0.0, cosV);
    const real alpha = ggxAlpha(roughness);
    // G2 / G1 = (1 + Lambda_v) / (1 + Lambda_v + Lambda_l), the viewer's Lambda taken once.
    const real lambdaView = ggxLambda(cosV, alpha);
    const int sides = steps / 2;
    real sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        const real w = (real(i) + 0.5) / real(steps);
        const real u1 = 1.0 - (1.0 - w) * (1.0 - w), jacobian = 2.0 * (1.0 - w);
        for (int j = 0; j < sides; ++j) {
            // 2 pi u2 from -pi/2 to pi/2: the visible normals on one side of the plane.
            const real u2 = 0.5 * ((real(j) + 0.5) / real(sides) - 0.5);
            const real3 m = sampleGgxVisibleNormal(toViewer, alpha, u1, u2);
            const real cosMicro = max(0.0, dot(m, toViewer));
            const real fresnel = eta > 0.0 ? fresnelDielectric(cosMicro, eta) : 1.0;
            real weight = 0.0;
            const real3 reflected = reflectAbout(toViewer, m);
            if (reflected.z > 0.0) weight += fresnel / (1.0 + lambdaView + ggxLambda(reflected.z, alpha));
            real3 refracted;
            if (eta > 0.0 && refractThrough(toViewer, m, eta, refracted) && refracted.z < 0.0) {
                weight += (1.0 - fresnel) / (1.0 + lambdaView + ggxLambda(-refracted.z, alpha));
            }
            sum += jacobian * weight;
        }
    }
    return (1.0 + lambdaView) * sum / (real(steps) * real(sides));
}

// The tables' coordinate in [0, 1] for a viewer at cosine cosView, and its inverse.
VKRT_FN real ggxAlbedoCosCoordinate(real cosView) { return sqrt(clamp(cosView, 0.0, 1.0)); }

VKRT_FN real ggxAlbedoCosAt(real x) { return x * x; }

// The dielectric table's coordinate in [0, 1] for relative index eta: with s = (eta - 1) / (eta + 1), from
// -1 (eta = 0) to 1 (eta = infinity), 1/2 + sign(s) sqrt(|s|) / 2, which puts entries closest together
// around eta = 1. (Clamped to indices 1/3 to 3, the table under-compensated beyond them: a rough glass sphere
// of index 10 in a white furnace kept 0.74 of the light, one of infinite index, which reflects everything
// like a white metal, 0.48.)
VKRT_FN real ggxDielectricEtaCoordinate(real eta) {
    const real s = clamp((eta - 1.0) / (eta + 1.0), -1.0, 1.0);
    const real u = sqrt(abs(s));
    return 0.5 + 0.5 * (s < 0.0 ? -u : u);
}

// The relative index at the dielectric table's coordinate x (ggxDielectricEtaCoordinate's inverse), from 1e-6
// to 1e6 at the ends.
VKRT_FN real ggxDielectricEtaAt(real x) {
    const real u = 2.0 * x - 1.0;
    const real s = u * abs(u);
    return clamp((1.0 + s) / max(1.0 - s, 1e-12), 1e-6, 1e6);
}

#ifdef VKRT_HAS_ROUGH_SPECULAR
// E(cosView, roughness) of the conductor table the device holds (VKRT_DEVICE(ggxAlbedoTable)(entry)).
VKRT_DEVICE_TEMPLATE
VKRT_FN real ggxAlbedo(VKRT_DEVICE_PARAM real cosView, real roughness) {
    const real last = real(VKRT_GGX_ALBEDO_SIZE - 1);
    const real x = ggxAlbedoCosCoordinate(cosView) * last, y = clamp(roughness, 0.0, 1.0) * last;
    const int i = min(int(x), VKRT_GGX_ALBEDO_SIZE - 2), j = min(int(y), VKRT_GGX_ALBEDO_SIZE - 2);
    const real fx = x - real(i), fy = y - real(j);
    const uint row = uint(j * VKRT_GGX_ALBEDO_SIZE + i);
    const uint size = uint(VKRT_GGX_ALBEDO_SIZE);
    return (1.0 - fy) * ((1.0 - fx) * real(VKRT_DEVICE(ggxAlbedoTable)(row)) +
                         fx * real(VKRT_DEVICE(ggxAlbedoTable)(row + 1u))) +
           fy * ((1.0 - fx) * real(VKRT_DEVICE(ggxAlbedoTable)(row + size)) +
                 fx * real(VKRT_DEVICE(ggxAlbedoTable)(row + size + 1u)));
}

#if defined(VKRT_HAS_VOLUMES) && defined(VKRT_HAS_ROUGH_REFRACTION)
// E_eta(cosView, roughness, eta) of the dielectric table the device holds
// (VKRT_DEVICE(ggxDielectricAlbedoTable)(entry)).
VKRT_DEVICE_TEMPLATE
VKRT_FN real ggxDielectricAlbedo(VKRT_DEVICE_PARAM real cosView, real roughness, real eta) {
    const int sizeX = VKRT_GGX_DIELECTRIC_COS_SIZE, sizeY = VKRT_GGX_DIELECTRIC_ROUGHNESS_SIZE;
    const int sizeZ = VKRT_GGX_DIELECTRIC_ETA_SIZE;
    const real x = ggxAlbedoCosCoordinate(cosView) * real(sizeX - 1);
    const real y = clamp(roughness, 0.0, 1.0) * real(sizeY - 1);
    const real z = ggxDielectricEtaCoordinate(eta) * real(sizeZ - 1);
    const int i = min(int(x), sizeX - 2), j = min(int(y), sizeY - 2), k = min(int(z), sizeZ - 2);
    const real fx = x - real(i), fy = y - real(j), fz = z - real(k);
    real result = 0.0;
    VKRT_UNROLL for (int corner = 0; corner < 8; ++corner) {
        const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
        const real weight = (di == 1 ? fx : 1.0 - fx) * (dj == 1 ? fy : 1.0 - fy) * (dk == 1 ? fz : 1.0 - fz);
        const uint entry = uint(((k + dk) * sizeY + j + dj) * sizeX + i + di);
        result += weight * real(VKRT_DEVICE(ggxDielectricAlbedoTable)(entry));
    }
    return result;
}
#endif
#endif

VKRT_SHADING_END

#endif  // VKRT_ENERGY_COMPENSATION_H
