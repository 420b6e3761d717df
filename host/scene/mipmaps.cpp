#include "scene/mipmaps.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vkrt {
namespace {

// sRGB-encoded bytes to linear values, and back with rounding to the nearest byte.
const std::array<double, 256>& srgbDecodeTable() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[i] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

uint8_t srgbEncode(double linear) {
    const double c = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    return static_cast<uint8_t>(std::clamp(std::lround(c * 255.0), 0L, 255L));
}

// The next level of `above`: each texel the mean of the (up to) 2x2 texels it covers.
TextureLevel halve(const TextureLevel& above, bool srgb) {
    TextureLevel level;
    level.width = std::max(1, above.width / 2);
    level.height = std::max(1, above.height / 2);
    level.rgba.resize(static_cast<size_t>(level.width) * level.height * 4);
    const std::array<double, 256>& decode = srgbDecodeTable();
    for (int y = 0; y < level.height; ++y) {
        for (int x = 0; x < level.width; ++x) {
            for (int c = 0; c < 4; ++c) {
                const bool colour = srgb && c < 3;
                double sum = 0.0;
                for (int dy = 0; dy < 2; ++dy) {
                    for (int dx = 0; dx < 2; ++dx) {
                        const int sx = std::min(2 * x + dx, above.width - 1);
                        const int sy = std::min(2 * y + dy, above.height - 1);
                        const uint8_t value = above.rgba[(static_cast<size_t>(sy) * above.width + sx) * 4 + c];
                        sum += colour ? decode[value] : value;
                    }
                }
                const double mean = sum / 4.0;
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
