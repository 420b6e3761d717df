// Texture lookups: wrap modes, sRGB decoding and bilinear or nearest filtering of RGBA8 texels. A texture is
// described by its GpuTexture (shared.h); the device returns the packed texel at an index
// (VKRT_DEVICE(texel)), red in the lowest byte.
#ifndef VKRT_TEXTURE_SAMPLING_H
#define VKRT_TEXTURE_SAMPLING_H

#include "shading_language.h"
#include "shared.h"

#define VKRT_WRAP_REPEAT 0u
#define VKRT_WRAP_CLAMP 1u
#define VKRT_WRAP_MIRROR 2u
// GpuTexture::flags: wrap S in bits 0-1, wrap T in bits 2-3 (VKRT_WRAP_*), bit 4 nearest filtering.
#define VKRT_TEXTURE_NEAREST 16u
// GpuTextureBinding::flags: the texels are sRGB-encoded colours (else linear data).
#define VKRT_BINDING_SRGB 1u
// GpuTextureBinding::flags: the binding reads the second texture coordinate set (TEXCOORD_1).
#define VKRT_BINDING_TEXCOORD1 2u

VKRT_SHADING_BEGIN

#ifdef __cplusplus
using gpu::GpuTexture;
using gpu::GpuTextureBinding;
#endif

// i modulo n > 0, in [0, n), with both operands of % non-negative (GLSL leaves % of negatives undefined).
VKRT_FN int positiveModulo(int i, int n) { return i >= 0 ? i % n : n - 1 - ((-1 - i) % n); }

// Texel coordinate i of a row or column of `size` texels, wrapped.
VKRT_FN uint wrapTexel(int i, int size, uint mode) {
    if (mode == VKRT_WRAP_CLAMP) return uint(clamp(i, 0, size - 1));
    if (mode == VKRT_WRAP_MIRROR) {
        const int m = positiveModulo(i, 2 * size);
        return uint(m < size ? m : 2 * size - 1 - m);
    }
    return uint(positiveModulo(i, size));
}

VKRT_FN real srgbToLinear(real encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : pow((encoded + 0.055) / 1.055, 2.4);
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
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 textureTexel(VKRT_DEVICE_PARAM GpuTexture texture, int x, int y, bool srgb) {
    const uint column = wrapTexel(x, int(texture.width), texture.flags & 3u);
    const uint row = wrapTexel(y, int(texture.height), (texture.flags >> 2u) & 3u);
    return decodeTexel(VKRT_DEVICE(texel)(texture.firstTexel + row * texture.width + column), srgb);
}

// Linear RGBA at texture coordinate `uv` (glTF: origin at the top-left of the image). Texel centres sit at
// half-integer positions; bilinear unless the sampler asks for nearest.
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 sampleTexture(VKRT_DEVICE_PARAM GpuTexture texture, real2 uv, bool srgb) {
    if (texture.width == 0u || texture.height == 0u) return real4(1.0);  // no image: the factor alone
    const real x = uv.x * real(texture.width) - 0.5, y = uv.y * real(texture.height) - 0.5;
    if ((texture.flags & VKRT_TEXTURE_NEAREST) != 0u) {
        return textureTexel(VKRT_DEVICE_ARG texture, int(floor(x + 0.5)), int(floor(y + 0.5)), srgb);
    }
    const real x0 = floor(x), y0 = floor(y);
    const real fx = x - x0, fy = y - y0;
    const int ix = int(x0), iy = int(y0);
    return (1.0 - fx) * (1.0 - fy) * textureTexel(VKRT_DEVICE_ARG texture, ix, iy, srgb) +
           fx * (1.0 - fy) * textureTexel(VKRT_DEVICE_ARG texture, ix + 1, iy, srgb) +
           (1.0 - fx) * fy * textureTexel(VKRT_DEVICE_ARG texture, ix, iy + 1, srgb) +
           fx * fy * textureTexel(VKRT_DEVICE_ARG texture, ix + 1, iy + 1, srgb);
}

// A material's texture binding (a GpuTextureBinding) at a hit: the device maps the hit's coordinates
// (barycentrics on triangles, texture coordinates on spheres) to the primitive's texture coordinates, which the
// binding transforms.
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 sampleBinding(VKRT_DEVICE_PARAM int binding, uint primitive, real2 hitUv) {
    VKRT_IN(GpuTextureBinding) b = VKRT_DEVICE(textureBinding)(binding);
    return sampleTexture(VKRT_DEVICE_ARG VKRT_DEVICE(textureInfo)(b.texture),
                         transformUv(b, VKRT_DEVICE(textureCoordinates)(primitive, hitUv,
                                                                         (b.flags & VKRT_BINDING_TEXCOORD1) != 0u ? 1u : 0u)),
                         (b.flags & VKRT_BINDING_SRGB) != 0u);
}
#endif

// A colour factor times its texture binding (-1: none) at a hit.
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 textured(VKRT_DEVICE_PARAM real3 factor, int binding, uint primitive, real2 hitUv) {
#ifdef VKRT_HAS_TEXTURES
    if (binding >= 0) {
        const real4 color = sampleBinding(VKRT_DEVICE_ARG binding, primitive, hitUv);
        return factor * real3(color.x, color.y, color.z);
    }
#endif
    return factor;
}

VKRT_SHADING_END

#endif  // VKRT_TEXTURE_SAMPLING_H
