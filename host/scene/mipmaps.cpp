#include "scene/mipmaps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "texture_sampling.h"

namespace vkrt {
namespace {

// sRGB-encoded bytes to linear values, and back with rounding to the nearest byte.
const std::array<double, 256>& srgbDecodeTable() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) t[i] = shading::srgbToLinear(i / 255.0);
        return t;
    }();
    return table;
}

uint8_t srgbEncode(double linear) {
    return static_cast<uint8_t>(std::clamp(std::lround(shading::linearToSrgb(linear) * 255.0), 0L, 255L));
}

// The source texels a destination texel covers along one axis when `from` texels become `to`: a box of
// from / to texels (2, or between 2 and 3 for an odd size), each source texel weighted by its overlap.
std::vector<std::vector<std::pair<int, double>>> boxWeights(int from, int to) {
    std::vector<std::vector<std::pair<int, double>>> weights(to);
    const double scale = static_cast<double>(from) / to;
    for (int d = 0; d < to; ++d) {
        const double begin = d * scale, end = (d + 1) * scale;
        for (int s = static_cast<int>(std::floor(begin)); s < std::min(from, static_cast<int>(std::ceil(end))); ++s) {
            const double overlap = std::min(end, s + 1.0) - std::max(begin, static_cast<double>(s));
            if (overlap > 0.0) weights[d].emplace_back(s, overlap / scale);
        }
    }
    return weights;
}

// The next level of `above`: each texel the mean of the texels of `above` it covers (a 2x2 box for even sizes,
// a wider one with fractional weights for odd sizes, so every texel above counts equally).
TextureLevel halve(const TextureLevel& above, bool srgb) {
    TextureLevel level;
    level.width = std::max(1, above.width / 2);
    level.height = std::max(1, above.height / 2);
    level.rgba.resize(static_cast<size_t>(level.width) * level.height * 4);
    const std::array<double, 256>& decode = srgbDecodeTable();
    const auto columns = boxWeights(above.width, level.width), rows = boxWeights(above.height, level.height);
    for (int y = 0; y < level.height; ++y) {
        for (int x = 0; x < level.width; ++x) {
            for (int c = 0; c < 4; ++c) {
                const bool colour = srgb && c < 3;
                double mean = 0.0;
                for (const auto& [sy, wy] : rows[y]) {
                    for (const auto& [sx, wx] : columns[x]) {
                        const uint8_t value = above.rgba[(static_cast<size_t>(sy) * above.width + sx) * 4 + c];
                        mean += wx * wy * (colour ? decode[value] : value);
                    }
                }
                level.rgba[(static_cast<size_t>(y) * level.width + x) * 4 + c] =
                    colour ? srgbEncode(mean)
                           : static_cast<uint8_t>(std::clamp(std::lround(mean), 0L, 255L));
            }
        }
    }
    return level;
}

}  // namespace

std::vector<TextureLevel> mipmapChain(const Texture& texture, bool srgb) {
    std::vector<TextureLevel> levels;
    TextureLevel current{texture.width, texture.height, texture.rgba};
    while (current.width > 1 || current.height > 1) {
        current = halve(current, srgb);
        levels.push_back(current);
    }
    return levels;
}

}  // namespace vkrt
