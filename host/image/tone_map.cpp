#include "image/tone_map.h"

#include <algorithm>
#include <cmath>

namespace vkrt {
namespace {

// Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve" (2015): (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) +
// 0.14).
double acesNarkowicz(double x) {
    return std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Khronos PBR Neutral (https://github.com/KhronosGroup/ToneMapping, PBR_Neutral): a small offset lifts the
// darkest channel's floor, colours pass unchanged below a peak of 0.76, and brighter ones are compressed
// towards 1 and desaturated in proportion to the compression.
glm::dvec3 pbrNeutral(glm::dvec3 color) {
    constexpr double startCompression = 0.8 - 0.04;
    constexpr double desaturation = 0.15;
    const double x = std::min({color.r, color.g, color.b});
    const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    const double peak = std::max({color.r, color.g, color.b});
    if (peak < startCompression) return color;
    constexpr double d = 1.0 - startCompression;
    const double newPeak = 1.0 - d * d / (peak + d - startCompression);
    color *= newPeak / peak;
    const double g = 1.0 - 1.0 / (desaturation * (peak - newPeak) + 1.0);
    return glm::mix(color, glm::dvec3(newPeak), g);
}

}  // namespace

const char* toneMapName(ToneMap toneMap) {
    switch (toneMap) {
        case ToneMap::Clamp:
            return "clamp";
        case ToneMap::Aces:
            return "aces";
        case ToneMap::PbrNeutral:
        default:
            return "pbr-neutral";
    }
}

std::optional<ToneMap> toneMapFromName(const std::string& name) {
    for (ToneMap t : {ToneMap::Clamp, ToneMap::Aces, ToneMap::PbrNeutral}) {
        if (name == toneMapName(t)) return t;
    }
    return std::nullopt;
}

glm::dvec3 toneMap(glm::dvec3 linear, ToneMap toneMap, double exposure) {
    glm::dvec3 v = linear * std::exp2(exposure);
    for (int c = 0; c < 3; ++c) {
        if (!(v[c] > 0.0)) v[c] = 0.0;  // negative and NaN both map to black
        // Beyond any curve's shoulder, and below where the curves' squares overflow (infinity over infinity
        // made a large exposure's white black).
        v[c] = std::min(v[c], 1e30);
    }
    switch (toneMap) {
        case ToneMap::Aces:
            v = {acesNarkowicz(v.r), acesNarkowicz(v.g), acesNarkowicz(v.b)};
            break;
        case ToneMap::PbrNeutral:
            v = pbrNeutral(v);
            break;
        case ToneMap::Clamp:
        default:
            break;
    }
    return glm::clamp(v, 0.0, 1.0);
}

}  // namespace vkrt
