#include "scene/ggx_albedo_tables.h"

#include "common/parallel_for.h"
#include "energy_compensation.h"

namespace vkrt {
namespace {

// Cells of the midpoint rule per axis (shading::ggxAlbedoIntegral): the entries are within 0.2% of the
// integral, well below the error of interpolating between them. The dielectric's 6400 entries take about a
// quarter of a second of one core.
constexpr int kConductorSteps = 32;
constexpr int kDielectricSteps = 24;

// Fills entry e of `count` by `entry(e)` on every hardware thread.
template <typename Entry>
std::vector<float> tabulate(size_t count, Entry entry) {
    std::vector<float> values(count);
    parallelFor(count, threadCount(0), [&](size_t e, unsigned) { values[e] = static_cast<float>(entry(e)); });
    return values;
}

}  // namespace

const std::vector<float>& ggxAlbedoTable() {
    static const std::vector<float> table = [] {
        constexpr int kSize = VKRT_GGX_ALBEDO_SIZE;
        return tabulate(kSize * kSize, [](size_t e) {
            const double cosView = shading::ggxAlbedoCosAt(static_cast<double>(e % kSize) / (kSize - 1));
            const double roughness = static_cast<double>(e / kSize) / (kSize - 1);
            return shading::ggxAlbedoIntegral(cosView, roughness, 0.0, kConductorSteps);
        });
    }();
    return table;
}

const std::vector<float>& ggxDielectricAlbedoTable() {
    static const std::vector<float> table = [] {
        constexpr int kCos = VKRT_GGX_DIELECTRIC_COS_SIZE, kRoughness = VKRT_GGX_DIELECTRIC_ROUGHNESS_SIZE;
        constexpr int kEta = VKRT_GGX_DIELECTRIC_ETA_SIZE;
        return tabulate(kCos * kRoughness * kEta, [](size_t e) {
            const double cosView = shading::ggxAlbedoCosAt(static_cast<double>(e % kCos) / (kCos - 1));
            const double roughness = static_cast<double>(e / kCos % kRoughness) / (kRoughness - 1);
            const double eta =
                shading::ggxDielectricEtaAt(static_cast<double>(e / (kCos * kRoughness)) / (kEta - 1));
            return shading::ggxAlbedoIntegral(cosView, roughness, eta, kDielectricSteps);
        });
    }();
    return table;
}

bool hasRoughSpecular(const Material& material) {
    const bool reflects =
        material.metallic > 0.0f || material.specularFactor > 0.0f || material.transmission > 0.0f;
    const bool roughBase = material.roughness >= VKRT_MIRROR_ROUGHNESS && reflects;
    const bool roughCoat = material.clearcoat > 0.0f && material.clearcoatRoughness >= VKRT_MIRROR_ROUGHNESS;
    return roughBase || roughCoat;
}

bool refractsRoughly(const Material& material) {
    return material.transmission > 0.0f && material.hasVolume() &&
           material.roughness >= VKRT_MIRROR_ROUGHNESS;
}

}  // namespace vkrt
