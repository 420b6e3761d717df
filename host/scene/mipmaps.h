// Mipmap chains of 8-bit RGBA textures: each level half the size of the one before (rounded down, at least
// one texel), down to 1x1, every texel the mean of the 2x2 texels above it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

struct TextureLevel {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
};

// The levels below `texture` itself (level 0), smallest last. Colours that are sRGB-encoded (`srgb`) are
// averaged as linear light and encoded again, so a minified checker of black and white keeps the brightness
// of its mean; alpha and linear data are averaged as stored. An odd size is halved by a box a little wider than
// 2 texels with fractional weights, so every texel of the level above counts equally.
std::vector<TextureLevel> mipmapChain(const Texture& texture, bool srgb);

// The sizes of the levels below a width x height level 0: each half the one before (rounded down, at least
// 1), down to 1 x 1.
struct LevelSize {
    int width = 0;
    int height = 0;
    size_t texels() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
};
std::vector<LevelSize> mipmapLevelSizes(int width, int height);

// The texels of all the levels below level 0 of a width x height texture.
size_t mipmapChainTexels(int width, int height);

// mipmapChain's levels, one after the other, written to `out` (mipmapChainTexels x 4 bytes); each level's
// rows are shared among `threads` threads (the caller's among them). The same bytes as mipmapChain's. `out` is
// written once and never read (it may be a GPU's mapped memory).
void writeMipmapChain(const Texture& texture, bool srgb, uint8_t* out, unsigned threads);

}  // namespace vkrt
