#include "scene/mipmaps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

#include "common/parallel_for.h"
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

// srgbEncode by a search of the 255 boundaries between bytes (a pow per channel was most of the time mipmaps
// took). Within 1e-9 of a boundary, whose tabulated place may differ from the formula's in the last bits,
// the formula decides, so every byte is the one srgbEncode gives.
uint8_t srgbEncodeFast(double linear) {
    static const std::array<double, 255> boundaries = [] {
        std::array<double, 255> b{};  // b[k]: where bytes k and k + 1 meet, as linear light
        for (int k = 0; k < 255; ++k) b[k] = shading::srgbToLinear((k + 0.5) / 255.0);
        return b;
    }();
    const size_t k = std::upper_bound(boundaries.begin(), boundaries.end(), linear) - boundaries.begin();
    const bool nearBoundary = (k > 0 && linear - boundaries[k - 1] < 1e-9) ||
                              (k < boundaries.size() && boundaries[k] - linear < 1e-9);
    return nearBoundary || !(linear >= 0.0) ? srgbEncode(linear) : static_cast<uint8_t>(k);
}

// A mean of bytes (in [0, 255], or a rounding above) to the nearest byte, halves up: std::lround's result for
// such values, without its call.
uint8_t roundToByte(double mean) {
    const int whole = static_cast<int>(mean);  // mean >= 0: truncation is floor, and mean - whole is exact
    return static_cast<uint8_t>(std::min(255, whole + (mean - whole >= 0.5 ? 1 : 0)));
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

// The level `below` (belowWidth x belowHeight) of the RGBA8 texels `above` (width x height): each texel the
// mean of the texels above it covers (a 2x2 box for even sizes, a wider one with fractional weights for odd
// sizes, so every texel above counts equally). Rows are shared among `threads` threads.
void halveInto(const uint8_t* above, int width, int height, uint8_t* below, int belowWidth, int belowHeight,
               bool srgb, unsigned threads) {
    const std::array<double, 256>& decode = srgbDecodeTable();
    // Small levels on this thread alone: starting threads would cost more.
    const unsigned rowThreads = static_cast<size_t>(belowWidth) * belowHeight >= (1u << 14) ? threads : 1u;
    if (width == 2 * belowWidth && height == 2 * belowHeight) {
        // Even sizes, most levels: the 2x2 box of the general loop below, in its order of operations (each
        // weight 0.5 x 0.5 = 0.25, exact), so every byte is the same; linear channels' sums of four bytes,
        // exact in integers, rounded halves up as roundToByte does. About three times as fast.
        parallelFor(static_cast<size_t>(belowHeight), rowThreads, [&](size_t y, unsigned) {
            const uint8_t* top = above + 2 * y * static_cast<size_t>(width) * 4;
            const uint8_t* bottom = top + static_cast<size_t>(width) * 4;
            uint8_t* out = below + y * static_cast<size_t>(belowWidth) * 4;
            for (int x = 0; x < belowWidth; ++x, top += 8, bottom += 8, out += 4) {
                for (int c = 0; c < 4; ++c) {
                    if (srgb && c < 3) {
                        const double mean = 0.0 + 0.25 * decode[top[c]] + 0.25 * decode[top[c + 4]] +
                                            0.25 * decode[bottom[c]] + 0.25 * decode[bottom[c + 4]];
                        out[c] = srgbEncodeFast(mean);
                    } else {
                        out[c] =
                            static_cast<uint8_t>((top[c] + top[c + 4] + bottom[c] + bottom[c + 4] + 2) >> 2);
                    }
                }
            }
        });
        return;
    }
    const auto columns = boxWeights(width, belowWidth), rows = boxWeights(height, belowHeight);
    parallelFor(static_cast<size_t>(belowHeight), rowThreads, [&](size_t y, unsigned) {
        for (int x = 0; x < belowWidth; ++x) {
            for (int c = 0; c < 4; ++c) {
                const bool colour = srgb && c < 3;
                double mean = 0.0;
                for (const auto& [sy, wy] : rows[y]) {
                    for (const auto& [sx, wx] : columns[x]) {
                        const uint8_t value = above[(static_cast<size_t>(sy) * width + sx) * 4 + c];
                        mean += wx * wy * (colour ? decode[value] : value);
                    }
                }
                below[(y * belowWidth + x) * 4 + c] = colour ? srgbEncodeFast(mean) : roundToByte(mean);
            }
        }
    });
}

}  // namespace

std::vector<LevelSize> mipmapLevelSizes(int width, int height) {
    std::vector<LevelSize> sizes;
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        sizes.push_back({width, height});
    }
    return sizes;
}

size_t mipmapChainTexels(int width, int height) {
    size_t texels = 0;
    for (const LevelSize& level : mipmapLevelSizes(width, height)) texels += level.texels();
    return texels;
}

void writeMipmapChain(const Texture& texture, bool srgb, uint8_t* out, unsigned threads) {
    // `out` is only written: it may be a GPU's memory mapped for the host, which a discrete GPU maps uncached
    // (reading it back is the likely reason Avocado's renders on an H200 took 1.5 s for 2 ms of tracing). Each
    // level is halved from the one above kept in host memory (two buffers, in turn).
    std::vector<uint8_t> levels[2];
    const uint8_t* above = texture.rgba->data();
    LevelSize aboveSize{texture.width, texture.height};
    int next = 0;
    for (const LevelSize& level : mipmapLevelSizes(texture.width, texture.height)) {
        std::vector<uint8_t>& current = levels[next];
        current.resize(level.texels() * 4);
        halveInto(above, aboveSize.width, aboveSize.height, current.data(), level.width, level.height, srgb, threads);
        std::memcpy(out, current.data(), current.size());
        above = current.data();
        aboveSize = level;
        out += current.size();
        next = 1 - next;
    }
}

std::vector<TextureLevel> mipmapChain(const Texture& texture, bool srgb) {
    std::vector<uint8_t> chain(mipmapChainTexels(texture.width, texture.height) * 4);
    writeMipmapChain(texture, srgb, chain.data(), 1);
    std::vector<TextureLevel> levels;
    auto next = chain.begin();
    for (const LevelSize& level : mipmapLevelSizes(texture.width, texture.height)) {
        const auto end = next + static_cast<std::ptrdiff_t>(level.texels() * 4);
        levels.push_back({level.width, level.height, std::vector<uint8_t>(next, end)});
        next = end;
    }
    return levels;
}

}  // namespace vkrt
