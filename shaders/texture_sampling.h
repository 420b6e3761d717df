// Texture lookups: wrap modes, sRGB decoding, bilinear or nearest filtering of RGBA8 texels, and mipmap levels
// chosen by ray cones. A texture is described by its GpuTexture (shared.h); the device returns the packed texel
// at an index (VKRT_DEVICE(texel)), red in the lowest byte.
#ifndef VKRT_TEXTURE_SAMPLING_H
#define VKRT_TEXTURE_SAMPLING_H

#include "shading_language.h"
#include "shared.h"
#include "texture_density.h"

#define VKRT_WRAP_REPEAT 0u
#define VKRT_WRAP_CLAMP 1u
#define VKRT_WRAP_MIRROR 2u
// GpuTexture::flags: wrap S in bits 0-1, wrap T in bits 2-3 (VKRT_WRAP_*), bit 4 nearest magnification, bit 5
// nearest minification (within a level), bits 6-7 the mipmap mode, bits 8-12 the number of levels (level 0
// and its mipmaps, stored one after the other from firstTexel).
#define VKRT_TEXTURE_NEAREST 16u
#define VKRT_TEXTURE_MIN_NEAREST 32u
#define VKRT_MIPMAP_SHIFT 6u
#define VKRT_MIPMAP_NONE 0u     // minified textures read level 0
#define VKRT_MIPMAP_NEAREST 1u  // the nearest level
#define VKRT_MIPMAP_LINEAR 2u   // the two nearest levels, blended
#define VKRT_LEVELS_SHIFT 8u
// GpuTextureBinding::flags: the texels are sRGB-encoded colours (else linear data).
#define VKRT_BINDING_SRGB 1u
// GpuTextureBinding::flags: the binding reads the second texture coordinate set (TEXCOORD_1).
#define VKRT_BINDING_TEXCOORD1 2u

VKRT_SHADING_BEGIN

#ifdef __cplusplus
using gpu::GpuTexture;
using gpu::GpuTextureBinding;
#endif

// i modulo n > 0, in [0, n), with both operands of % non-negative (GLSL leaves % of negatives undefined). One
// division: a SIMD machine without a vector divide (lavapipe's x86) divides lane by lane.
VKRT_FN int positiveModulo(int i, int n) {
    const int r = (i >= 0 ? i : -1 - i) % n;
    return i >= 0 ? r : n - 1 - r;
}

// Texel coordinates i and i + 1 of a row or column of `size` texels, wrapped (a bilinear footprint's two
// columns or rows). One modulo for both, which repeat and mirrored repeat share: on lavapipe every branch runs,
// and each modulo is eight divisions.
VKRT_FN uvec2 wrapTexels(int i, int size, uint mode) {
    if (mode == VKRT_WRAP_CLAMP) return uvec2(uint(clamp(i, 0, size - 1)), uint(clamp(i + 1, 0, size - 1)));
    const bool mirror = mode == VKRT_WRAP_MIRROR;
    const int period = mirror ? 2 * size : size;
    const int m0 = positiveModulo(i, period);
    const int m1 = m0 + 1 == period ? 0 : m0 + 1;  // (i + 1) modulo the period
    return uvec2(uint(mirror && m0 >= size ? 2 * size - 1 - m0 : m0),
                 uint(mirror && m1 >= size ? 2 * size - 1 - m1 : m1));
}

VKRT_FN real srgbToLinear(real encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : pow((encoded + 0.055) / 1.055, 2.4);
}

VKRT_FN real linearToSrgb(real linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

// An RGBA8 texel (red in the lowest byte) as RGB and alpha in [0, 1]; sRGB-encoded colour channels are
// decoded to linear (alpha and linear data are stored as they are).
VKRT_FN real4 decodeTexel(uint bits, bool srgb) {
    const real r = real(bits & 0xffu) / 255.0;
    const real g = real((bits >> 8u) & 0xffu) / 255.0;
    const real b = real((bits >> 16u) & 0xffu) / 255.0;
    const real a = real(bits >> 24u) / 255.0;
    if (!srgb) return real4(r, g, b, a);
    return real4(srgbToLinear(r), srgbToLinear(g), srgbToLinear(b), a);
}

// KHR_texture_transform: a binding's texture coordinates from the mesh's.
VKRT_FN real2 transformUv(VKRT_IN(GpuTextureBinding) binding, real2 uv) {
    return real2(real(binding.row0.x) * uv.x + real(binding.row0.y) * uv.y + real(binding.row0.z),
                 real(binding.row1.x) * uv.x + real(binding.row1.y) * uv.y + real(binding.row1.z));
}

#ifdef VKRT_HAS_TEXTURES
// Mipmap level `level` of `texture`, as a texture of its own: each level half the size of the one before
// (rounded down, at least 1), stored after it.
VKRT_FN GpuTexture textureLevel(GpuTexture texture, int level) {
    GpuTexture result = texture;
    for (int l = 0; l < level; ++l) {
        result.firstTexel += result.width * result.height;
        result.width = result.width > 1u ? result.width / 2u : 1u;
        result.height = result.height > 1u ? result.height / 2u : 1u;
    }
    return result;
}

// A texture coordinate far outside [0, 1] brought near it, so that its texel index stays within an int (an int
// conversion out of range is undefined: an offset of 1e9 on a row of 4 texels read the wrong texels on the
// CPU). By whole periods of 2, which repeat and mirrored repeat both repeat within; clamped ones to [-1, 2],
// beyond which every texel read is an edge's. One that is not finite (a transform's product overflowing
// single precision) reads at 0. Within [-2, 2] it is left as it is, the same bits as before.
VKRT_FN real nearTexture(real u, uint mode) {
    if (abs(u) <= 2.0) return u;
    if (!(abs(u) < 1.0e30)) return 0.0;
    if (mode == VKRT_WRAP_CLAMP) return clamp(u, -1.0, 2.0);
    return u - 2.0 * floor(0.5 * u);
}

// Linear RGBA of one level at texture coordinate `uv` (glTF: origin at the top-left of the image). Texel
// centres sit at half-integer positions; bilinear, or the nearest texel.
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 filterLevel(VKRT_DEVICE_PARAM GpuTexture texture, real2 uv, bool srgb, bool nearest) {
    const real x = nearTexture(uv.x, texture.flags & 3u) * real(texture.width) - 0.5,
               y = nearTexture(uv.y, (texture.flags >> 2u) & 3u) * real(texture.height) - 0.5;
    // The nearest texel is the bilinear sum's first term at weight 1, the others' 0 (exactly that texel): one
    // set of texel reads serves both filters.
    const real x0 = nearest ? floor(x + 0.5) : floor(x), y0 = nearest ? floor(y + 0.5) : floor(y);
    const real fx = nearest ? 0.0 : x - x0, fy = nearest ? 0.0 : y - y0;
    const uvec2 columns = wrapTexels(int(x0), int(texture.width), texture.flags & 3u);
    const uvec2 rows = texture.firstTexel + wrapTexels(int(y0), int(texture.height), (texture.flags >> 2u) & 3u) *
                                                texture.width;
    return (1.0 - fx) * (1.0 - fy) * decodeTexel(VKRT_DEVICE(texel)(rows.x + columns.x), srgb) +
           fx * (1.0 - fy) * decodeTexel(VKRT_DEVICE(texel)(rows.x + columns.y), srgb) +
           (1.0 - fx) * fy * decodeTexel(VKRT_DEVICE(texel)(rows.y + columns.x), srgb) +
           fx * fy * decodeTexel(VKRT_DEVICE(texel)(rows.y + columns.y), srgb);
}

// Linear RGBA at `uv` seen with level of detail `lod` (log2 of the texels one sample covers across): at
// most 0 the texture is magnified (the magnification filter on level 0), above it minified (the minification
// filter on the level or the two levels the mipmap mode picks, as OpenGL samples them).
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 sampleTexture(VKRT_DEVICE_PARAM GpuTexture texture, real2 uv, bool srgb, real lod) {
    if (texture.width == 0u || texture.height == 0u) return real4(1.0);  // no image: the factor alone
    bool nearest = (texture.flags & VKRT_TEXTURE_NEAREST) != 0u;
    int level = 0;
    real blend = 0.0;  // the weight of level + 1
#ifdef VKRT_HAS_MIPMAPS
    if (lod > 0.0) {
        nearest = (texture.flags & VKRT_TEXTURE_MIN_NEAREST) != 0u;
        const uint mode = (texture.flags >> VKRT_MIPMAP_SHIFT) & 3u;
        const real deepest = real(int((texture.flags >> VKRT_LEVELS_SHIFT) & 31u) - 1);
        if (mode == VKRT_MIPMAP_NEAREST) {
            level = int(min(floor(lod + 0.5), deepest));
        } else if (mode == VKRT_MIPMAP_LINEAR) {
            const real clamped = min(lod, deepest);
            level = int(floor(clamped));
            blend = clamped - real(level);
        }
    }
#endif
    // One lookup site for both levels: every inlined filter costs code and registers in the whole kernel. The
    // loop runs once where no level is blended (on lavapipe a SIMD group runs a loop's body for as long as any
    // of its lanes needs it, and every pass of it whole, so a second level is paid only where one is read).
    real4 result = real4(0.0);
    const int levels = blend > 0.0 ? 2 : 1;
    for (int k = 0; k < levels; ++k) {
        const real weight = k == 0 ? 1.0 - blend : blend;
        result += weight * filterLevel(VKRT_DEVICE_ARG textureLevel(texture, level + k), uv, srgb, nearest);
    }
    return result;
}

// A material's texture binding (a GpuTextureBinding) at a hit: the device maps the hit's coordinates
// (barycentrics on triangles, texture coordinates on spheres) to the primitive's texture coordinates, which the
// binding transforms. `footprint` is the width, in world units, of the surface one sample covers there (ray
// cones; 0: none, the finest level); the level of detail is its width in texels (Akenine-Moller et al.,
// "Texture Level of Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems, ch. 20, 2019): log2 of
// footprint x texture coordinates per world unit x texels per texture coordinate (the transform's scale
// included).
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 sampleBinding(VKRT_DEVICE_PARAM int binding, uint primitive, real2 hitUv, real footprint) {
    VKRT_IN(GpuTextureBinding) b = VKRT_DEVICE(textureBinding)(binding);
    const GpuTexture texture = VKRT_DEVICE(textureInfo)(b.texture);
    const uint set = (b.flags & VKRT_BINDING_TEXCOORD1) != 0u ? 1u : 0u;
    real lod = 0.0;
#ifdef VKRT_HAS_MIPMAPS
    if (footprint > 0.0) {
        const real scale = abs(real(b.row0.x) * real(b.row1.y) - real(b.row0.y) * real(b.row1.x));
        lod = log2(footprint * VKRT_DEVICE(textureDensity)(primitive, hitUv, set) *
                   sqrt(scale * real(texture.width) * real(texture.height)));
    }
#endif
    return sampleTexture(VKRT_DEVICE_ARG texture, transformUv(b, VKRT_DEVICE(textureCoordinates)(primitive, hitUv, set)),
                         (b.flags & VKRT_BINDING_SRGB) != 0u, lod);
}
#endif

// A colour factor times its texture binding (-1: none) at a hit seen with `footprint` (sampleBinding).
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 textured(VKRT_DEVICE_PARAM real3 factor, int binding, uint primitive, real2 hitUv, real footprint) {
#ifdef VKRT_HAS_TEXTURES
    if (binding >= 0) {
        const real4 color = sampleBinding(VKRT_DEVICE_ARG binding, primitive, hitUv, footprint);
        return factor * real3(color.x, color.y, color.z);
    }
#endif
    return factor;
}

VKRT_SHADING_END

#endif  // VKRT_TEXTURE_SAMPLING_H
