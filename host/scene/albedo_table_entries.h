// The directional-albedo tables both renderers read (energy_compensation.h's GGX tables, sheen.h's sheen
// table), entry by entry: each computed in double precision by the shared shading code and stored as a float.
// generate_albedo_tables.cpp tabulates them when vkrt is built (they take about a quarter of a second of one
// core, which every render paid at its start), and the tests recompute entries to check the built tables.
#pragma once

#include <algorithm>
#include <cstddef>

#include "energy_compensation.h"
#include "sheen.h"

namespace vkrt {

inline constexpr size_t kGgxAlbedoEntries = VKRT_GGX_ALBEDO_SIZE * VKRT_GGX_ALBEDO_SIZE;
inline constexpr size_t kGgxDielectricAlbedoEntries =
    VKRT_GGX_DIELECTRIC_COS_SIZE * VKRT_GGX_DIELECTRIC_ROUGHNESS_SIZE * VKRT_GGX_DIELECTRIC_ETA_SIZE;
inline constexpr size_t kSheenAlbedoEntries = VKRT_SHEEN_TABLE_SIZE * VKRT_SHEEN_TABLE_SIZE;

// Entry e of the conductor's table: E(cosView, roughness) with F = 1, cosView varying fastest. 32 midpoint
// cells per axis (shading::ggxAlbedoIntegral): within 0.2% of the integral, well below the error of
// interpolating between entries.
inline float ggxAlbedoEntry(size_t e) {
    constexpr int kSize = VKRT_GGX_ALBEDO_SIZE;
    const double cosView = shading::ggxAlbedoCosAt(static_cast<double>(e % kSize) / (kSize - 1));
    const double roughness = static_cast<double>(e / kSize) / (kSize - 1);
    return static_cast<float>(shading::ggxAlbedoIntegral(cosView, roughness, 0.0, 32));
}

// Entry e of the dielectric's table: E_eta(cosView, roughness, eta), reflection and refraction together,
// cosView varying fastest, then roughness. 24 cells per axis.
inline float ggxDielectricAlbedoEntry(size_t e) {
    constexpr int kCos = VKRT_GGX_DIELECTRIC_COS_SIZE, kRoughness = VKRT_GGX_DIELECTRIC_ROUGHNESS_SIZE;
    constexpr int kEta = VKRT_GGX_DIELECTRIC_ETA_SIZE;
    const double cosView = shading::ggxAlbedoCosAt(static_cast<double>(e % kCos) / (kCos - 1));
    const double roughness = static_cast<double>(e / kCos % kRoughness) / (kRoughness - 1);
    const double eta = shading::ggxDielectricEtaAt(static_cast<double>(e / (kCos * kRoughness)) / (kEta - 1));
    return static_cast<float>(shading::ggxAlbedoIntegral(cosView, roughness, eta, 24));
}

// Entry e of the sheen's table: E(cosView, roughness), sqrt(cosView) varying fastest; 64 x 64 midpoint cells
// (over half the circle of azimuths). Interpolating the entries is within 3% of the integral
// (tests/gpu_surface_test.cpp checks a point between entries against a finer integration). The fitted
// shadowing overestimates the albedo of the smoothest sheen seen at grazing angles (E reaches 1.6 at cos 0),
// and the entries keep it: addSheen (surface_response.h) divides such a lobe by E. From cos 2/31 on the
// integral stays below 1.
inline float sheenAlbedoEntry(size_t e) {
    constexpr int kSize = VKRT_SHEEN_TABLE_SIZE;
    const double root = static_cast<double>(e % kSize) / (kSize - 1);  // sqrt(cos(view))
    return static_cast<float>(
        shading::sheenAlbedoIntegral(root * root, static_cast<double>(e / kSize) / (kSize - 1), 64));
}

// The tables as built (generated/albedo_tables.cpp).
extern const float kGgxAlbedoTable[kGgxAlbedoEntries];
extern const float kGgxDielectricAlbedoTable[kGgxDielectricAlbedoEntries];
extern const float kSheenAlbedoTable[kSheenAlbedoEntries];

}  // namespace vkrt
