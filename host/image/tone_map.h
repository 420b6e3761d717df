// Tone mapping: linear radiance to the displayable range [0, 1] before a PNG's sRGB encoding. EXR and PFM
// stay linear.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace vkrt {

enum class ToneMap {
    Clamp,       // values above 1 clip (each channel on its own)
    Aces,        // Narkowicz's fit of the ACES filmic curve ("ACES Filmic Tone Mapping Curve", 2015)
    PbrNeutral,  // Khronos PBR Neutral: base colours show as authored up to 0.8, highlights roll off
};

// Khronos glTF-Sample-Viewer's default, so glTF assets look as they do there.
inline constexpr ToneMap kDefaultToneMap = ToneMap::PbrNeutral;

const char* toneMapName(ToneMap toneMap);
std::optional<ToneMap> toneMapFromName(const std::string& name);

// Exposure applies first (linear * 2^exposure); the result is in [0, 1]. Negative and NaN channels are 0.
glm::dvec3 toneMap(glm::dvec3 linear, ToneMap toneMap, double exposure = 0.0);

}  // namespace vkrt
