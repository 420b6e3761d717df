#include "scene/ggx_albedo_tables.h"

#include <iterator>

#include "scene/albedo_table_entries.h"

namespace vkrt {

const std::vector<float>& ggxAlbedoTable() {
    static const std::vector<float> table(std::begin(kGgxAlbedoTable), std::end(kGgxAlbedoTable));
    return table;
}

const std::vector<float>& ggxDielectricAlbedoTable() {
    static const std::vector<float> table(std::begin(kGgxDielectricAlbedoTable),
                                          std::end(kGgxDielectricAlbedoTable));
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
