#include "cpu/texture_lookup.h"

#include <algorithm>
#include <cmath>

namespace vkrt {
namespace {

int wrapTexel(int i, int size, WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return std::clamp(i, 0, size - 1);
        case WrapMode::MirroredRepeat: {
            const int period = 2 * size;
            int m = ((i % period) + period) % period;
            return m < size ? m : period - 1 - m;
        }
        case WrapMode::Repeat:
        default:
            return ((i % size) + size) % size;
    }
}

double srgbToLinear(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

glm::dvec4 texel(const Texture& texture, int x, int y) {
    x = wrapTexel(x, texture.width, texture.wrapS);
    y = wrapTexel(y, texture.height, texture.wrapT);
    const uint8_t* p = &texture.rgba[(static_cast<size_t>(y) * texture.width + x) * 4];
    return glm::dvec4(srgbToLinear(p[0] / 255.0), srgbToLinear(p[1] / 255.0), srgbToLinear(p[2] / 255.0),
                      p[3] / 255.0);
}

}  // namespace

glm::dvec4 sampleBaseColor(const Texture& texture, glm::dvec2 uv) {
    if (texture.rgba.empty()) return glm::dvec4(1.0);
    // Texel centres sit at half-integer positions.
    const double x = uv.x * texture.width - 0.5, y = uv.y * texture.height - 0.5;
    if (texture.nearest) {
        return texel(texture, static_cast<int>(std::floor(x + 0.5)), static_cast<int>(std::floor(y + 0.5)));
    }
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const int ix = static_cast<int>(x0), iy = static_cast<int>(y0);
    return (1 - fx) * (1 - fy) * texel(texture, ix, iy) + fx * (1 - fy) * texel(texture, ix + 1, iy) +
           (1 - fx) * fy * texel(texture, ix, iy + 1) + fx * fy * texel(texture, ix + 1, iy + 1);
}

}  // namespace vkrt
