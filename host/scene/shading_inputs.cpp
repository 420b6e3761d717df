#include "scene/shading_inputs.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "common/parallel_for.h"
#include "scene/mipmaps.h"
#include "scene/scene_error.h"
#include "texture_sampling.h"

namespace vkrt {
namespace {

uint32_t wrapBits(WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return VKRT_WRAP_CLAMP;
        case WrapMode::MirroredRepeat:
            return VKRT_WRAP_MIRROR;
        default:
            return VKRT_WRAP_REPEAT;
    }
}

// `offset` less a whole number of periods of 2, within which repeat and mirrored repeat both repeat: the same
// image, but the GPU's single-precision sum u + offset keeps u's fraction (4u + 65536 kept 7 bits of it, and
// the GPU's texels moved where the CPU's did not). A clamped axis is not periodic and keeps its offset.
float offsetWithinPeriod(float offset, WrapMode mode) {
    if (mode == WrapMode::ClampToEdge || !std::isfinite(offset)) return offset;
    return static_cast<float>(offset - 2.0 * std::floor(0.5 * static_cast<double>(offset)));  // exact
}

// A texture slot of `material` as a binding (sRGB where the slot holds colours): KHR_texture_transform's
// translation * rotation * scale as two matrix rows (TextureSlot::linearRows, then the offset).
int bind(const Material& material, const TextureSlot& slot, const std::vector<Texture>& textures,
         std::vector<gpu::GpuTextureBinding>& bindings) {
    if (!slot.used()) return -1;
    const bool srgb = material.holdsColour(&slot);
    const std::array<glm::vec2, 2> rows = slot.linearRows();
    const Texture& texture = textures.at(static_cast<size_t>(slot.texture));
    gpu::GpuTextureBinding binding{};
    binding.row0 = glm::vec3(rows[0], offsetWithinPeriod(slot.offset.x, texture.wrapS));
    binding.row1 = glm::vec3(rows[1], offsetWithinPeriod(slot.offset.y, texture.wrapT));
    binding.texture = slot.texture;
    binding.flags = (srgb ? VKRT_BINDING_SRGB : 0u) | (slot.texCoord == 1 ? VKRT_BINDING_TEXCOORD1 : 0u);
    bindings.push_back(binding);
    return static_cast<int>(bindings.size()) - 1;
}

}  // namespace

shading::SurfaceMaterial surfaceMaterial(const Material& m, const std::vector<Texture>& textures,
                                         std::vector<gpu::GpuTextureBinding>& bindings) {
    shading::SurfaceMaterial s;
    s.baseColor = glm::dvec3(glm::vec3(m.baseColor));
    s.metallic = m.metallic;
    s.emission = glm::dvec3(m.emission);
    s.roughness = m.roughness;
    s.attenuationColor = glm::dvec3(m.attenuationColor);
    s.attenuationDistance = m.attenuationDistance;
    s.transmission = m.transmission;
    s.ior = m.ior;
    s.volume = m.hasVolume();
    s.doubleSided = m.doubleSided;
    s.baseColorTexture = bind(m, m.baseColorTexture, textures, bindings);
    s.emissiveTexture = bind(m, m.emissiveTexture, textures, bindings);
    s.metallicRoughnessTexture = bind(m, m.metallicRoughnessTexture, textures, bindings);
    s.occlusionTexture = bind(m, m.occlusionTexture, textures, bindings);
    s.occlusionStrength = m.occlusionStrength;
    s.specularFactor = m.specularFactor;
    s.specularColor = glm::dvec3(m.specularColor);
    s.specularTexture = bind(m, m.specularTexture, textures, bindings);
    s.specularColorTexture = bind(m, m.specularColorTexture, textures, bindings);
    s.normalTexture = bind(m, m.normalTexture, textures, bindings);
    s.normalScale = m.normalScale;
    s.alphaMode = m.alphaMode == AlphaMode::Mask    ? VKRT_ALPHA_MASK
                  : m.alphaMode == AlphaMode::Blend ? VKRT_ALPHA_BLEND
                                                    : VKRT_ALPHA_OPAQUE;
    s.alpha = m.baseColor.a;
    s.alphaCutoff = m.alphaCutoff;
    s.transmissionTexture = bind(m, m.transmissionTexture, textures, bindings);
    s.unlit = m.unlit;
    s.clearcoat = m.clearcoat;
    s.clearcoatRoughness = m.clearcoatRoughness;
    s.clearcoatTexture = bind(m, m.clearcoatTexture, textures, bindings);
    s.clearcoatRoughnessTexture = bind(m, m.clearcoatRoughnessTexture, textures, bindings);
    s.clearcoatNormalTexture = bind(m, m.clearcoatNormalTexture, textures, bindings);
    s.clearcoatNormalScale = m.clearcoatNormalScale;
    s.sheenColor = glm::dvec3(m.sheenColor);
    s.sheenRoughness = m.sheenRoughness;
    s.sheenColorTexture = bind(m, m.sheenColorTexture, textures, bindings);
    s.sheenRoughnessTexture = bind(m, m.sheenRoughnessTexture, textures, bindings);
    s.textureSlots = shading::materialTextureSlots(s);
    return s;
}

shading::PunctualLightParams punctualLightParams(const PunctualLight& light) {
    shading::PunctualLightParams p;
    p.type = light.type == LightType::Point  ? VKRT_LIGHT_POINT
             : light.type == LightType::Spot ? VKRT_LIGHT_SPOT
                                             : VKRT_LIGHT_DIRECTIONAL;
    p.position = light.position;
    p.direction = light.direction;
    p.intensity = glm::dvec3(light.color) * static_cast<double>(light.intensity);
    p.range = light.range;
    p.cosOuter = std::cos(static_cast<double>(light.outerConeAngle));
    p.coneScale = 1.0 / std::max(0.001, std::cos(static_cast<double>(light.innerConeAngle)) - p.cosOuter);
    return p;
}

shading::CameraFrame cameraFrame(const Camera& camera, const Aabb& sceneBounds, int width, int height) {
    shading::CameraFrame frame;
    frame.projection = camera.projection == Projection::Orthographic ? VKRT_PROJECTION_ORTHOGRAPHIC
                                                                     : VKRT_PROJECTION_PERSPECTIVE;
    frame.position = camera.position;
    frame.forward = camera.forward;
    frame.right = camera.right;
    frame.up = camera.up;
    frame.tanHalfFov = std::tan(0.5 * camera.yfov);
    frame.xmag = camera.xmag;
    frame.ymag = camera.ymag;
    frame.lensRadius = camera.aperture;
    frame.focusDistance = camera.focusDistance;
    // The farthest corner of the bounds, a part in a million further (the GPU's float of it rounds down by
    // less).
    frame.sceneRadius = std::numeric_limits<double>::infinity();
    if (!sceneBounds.empty()) {
        double farthest = 0.0;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 at((corner & 1) ? sceneBounds.max.x : sceneBounds.min.x,
                                (corner & 2) ? sceneBounds.max.y : sceneBounds.min.y,
                                (corner & 4) ? sceneBounds.max.z : sceneBounds.min.z);
            farthest = std::max(farthest, glm::length(at - camera.position));
        }
        frame.sceneRadius = farthest * (1.0 + 1e-6);
    }
    frame.width = width;
    frame.height = height;
    return frame;
}

namespace {

// Whether a texture has mipmap levels (below level 0) in the packed array.
bool mipmapped(const Texture& t) {
    return t.mipmaps != MipmapMode::None && t.rgba && !t.rgba->empty();
}

// Which textures hold sRGB-encoded colours (their mipmaps are averaged as linear light).
std::vector<bool> colourTextures(const Scene& scene) {
    std::vector<bool> srgb(scene.textures.size(), false);
    for (const Material& m : scene.materials) {
        for (const TextureSlot* slot : m.textureSlots()) {
            if (slot->used() && m.holdsColour(slot)) srgb[slot->texture] = true;
        }
    }
    return srgb;
}

// Texels packed once for all the textures that show one image in one colour space: level 0, then the mipmaps
// when any of them has mipmaps (one without reads level 0 alone). Their samplers may differ: each texture's
// GpuTexture keeps its own, and the mipmaps depend only on the texels and the colour space.
struct TexelBlock {
    size_t texture = 0;  // the first texture that shows it
    bool srgb = false;
    bool mipmapped = false;
    size_t firstTexel = 0;
};

// Where the textures' texels lie in the packed array.
struct TexelLayout {
    std::vector<TexelBlock> blocks;
    std::vector<size_t> blockOf;  // by texture
    size_t texels = 0;            // all the blocks'
};

TexelLayout texelLayout(const Scene& scene) {
    TexelLayout layout;
    const std::vector<bool> srgb = colourTextures(scene);
    std::map<std::pair<const std::vector<uint8_t>*, bool>, size_t> blockIndex;
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& t = scene.textures[i];
        const auto [it, added] = blockIndex.try_emplace({t.rgba.get(), srgb[i]}, layout.blocks.size());
        if (added) layout.blocks.push_back({i, srgb[i], false, 0});
        layout.blocks[it->second].mipmapped |= mipmapped(t);
        layout.blockOf.push_back(it->second);
    }
    for (TexelBlock& block : layout.blocks) {
        const Texture& t = scene.textures[block.texture];
        block.firstTexel = layout.texels;
        layout.texels +=
            (t.rgba ? t.rgba->size() / 4 : 0) + (block.mipmapped ? mipmapChainTexels(t.width, t.height) : 0);
    }
    return layout;
}

}  // namespace

size_t packedTextureBytes(const Scene& scene) {
    return texelLayout(scene).texels * 4;
}

std::vector<gpu::GpuTexture> describeTextures(const Scene& scene) {
    const TexelLayout layout = texelLayout(scene);
    // The kernels and the reference address texels with 32 bits: past them a texture would read another's.
    if (layout.texels > std::numeric_limits<uint32_t>::max()) {
        throw SceneError("the textures hold " + std::to_string(layout.texels) +
                         " texels with their mipmaps; vkrt addresses at most 2^32 - 1");
    }
    std::vector<gpu::GpuTexture> textures;
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& t = scene.textures[i];
        const uint32_t mipmapBits = t.mipmaps == MipmapMode::Linear    ? VKRT_MIPMAP_LINEAR
                                    : t.mipmaps == MipmapMode::Nearest ? VKRT_MIPMAP_NEAREST
                                                                       : VKRT_MIPMAP_NONE;
        // Level 0 at the block's first texel, then its mipmaps (texture_sampling.h finds level l's first
        // texel).
        const uint32_t levels =
            1u + (mipmapped(t) ? static_cast<uint32_t>(mipmapLevelSizes(t.width, t.height).size()) : 0u);
        textures.push_back({static_cast<uint32_t>(layout.blocks[layout.blockOf[i]].firstTexel),
                            static_cast<uint32_t>(t.width), static_cast<uint32_t>(t.height),
                            wrapBits(t.wrapS) | (wrapBits(t.wrapT) << 2) |
                                (t.nearest ? VKRT_TEXTURE_NEAREST : 0u) |
                                (t.minNearest ? VKRT_TEXTURE_MIN_NEAREST : 0u) |
                                (mipmapBits << VKRT_MIPMAP_SHIFT) | (levels << VKRT_LEVELS_SHIFT)});
    }
    return textures;
}

void writeTexels(const Scene& scene, const std::vector<gpu::GpuTexture>& textures, uint32_t* texels) {
    // A texel's word holds red in its lowest byte: on a little-endian host, the RGBA bytes as they are.
    static_assert(std::endian::native == std::endian::little, "texels are packed as little-endian words");
    // Every level written once, in place: no copy of the packed texels (each copy first touches its pages, most
    // of what packing took); writeMipmapChain halves each level from a small host copy of the one above.
    for (const TexelBlock& block : texelLayout(scene).blocks) {
        const Texture& t = scene.textures[block.texture];
        if (!t.rgba || t.rgba->empty()) continue;
        uint8_t* const level0 = reinterpret_cast<uint8_t*>(texels + textures[block.texture].firstTexel);
        std::memcpy(level0, t.rgba->data(), t.rgba->size());
        if (block.mipmapped) writeMipmapChain(t, block.srgb, level0 + t.rgba->size(), threadCount(0));
    }
}

PackedTextures packTextures(const Scene& scene) {
    PackedTextures packed;
    packed.textures = describeTextures(scene);
    packed.texels.resize(packedTextureBytes(scene) / 4);
    writeTexels(scene, packed.textures, packed.texels.data());
    return packed;
}

}  // namespace vkrt
