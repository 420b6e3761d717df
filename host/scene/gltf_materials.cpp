#include "scene/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include <tiny_gltf.h>

#include "media.h"
#include "scene/gltf_extensions.h"
#include "scene/gltf_images.h"
#include "scene/gltf_material_extensions.h"
#include "scene/gltf_texture_slots.h"

namespace vkrt {
namespace {

WrapMode wrapMode(int mode) {
    if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::ClampToEdge;
    if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::MirroredRepeat;
    return WrapMode::Repeat;
}

// glTF's minFilter: nearest or bilinear within a level, and no, the nearest or blended mipmap levels. Absent,
// trilinear filtering.
void readMinFilter(int minFilter, Texture& texture) {
    switch (minFilter) {
        case TINYGLTF_TEXTURE_FILTER_NEAREST:
            texture.minNearest = true;
            texture.mipmaps = MipmapMode::None;
            break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR:
            texture.mipmaps = MipmapMode::None;
            break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
            texture.minNearest = true;
            texture.mipmaps = MipmapMode::Nearest;
            break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
            texture.mipmaps = MipmapMode::Nearest;
            break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
            texture.minNearest = true;
            break;
        default:  // LINEAR_MIPMAP_LINEAR or absent
            break;
    }
}

// Expand the image's 1 to 4 channels of 8 or 16 bits to 8-bit RGBA (16-bit values rounded to the nearest).
std::shared_ptr<const std::vector<uint8_t>> decodeImage(const GltfContext& context,
                                                        const tinygltf::Image& image, int imageIndex) {
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    const size_t bytesPerChannel = image.bits / 8;
    if (image.image.size() < pixels * image.component * bytesPerChannel) {
        context.fail(describeImage(context.model, imageIndex) + " has fewer pixels than its size");
    }
    auto rgba = std::make_shared<std::vector<uint8_t>>(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
        uint8_t channel[4] = {0, 0, 0, 255};
        for (int c = 0; c < image.component; ++c) {
            const size_t at = (p * image.component + c) * bytesPerChannel;
            if (bytesPerChannel == 1) {
                channel[c] = image.image[at];
            } else {
                // A 16-bit value v (little-endian, as tinygltf decodes) stands for v / 65535: the nearest
                // 8-bit value is round(v * 255 / 65535) = round(v / 257). (Its high byte, v / 256 rounded
                // down, was up to one step off: 0xff00 read as 255 for 254.)
                const uint32_t value = image.image[at] | (uint32_t{image.image[at + 1]} << 8);
                channel[c] = static_cast<uint8_t>((value + 128u) / 257u);
            }
        }
        if (image.component <= 2) {  // grey or grey + alpha
            channel[3] = image.component == 2 ? channel[1] : 255;
            channel[1] = channel[2] = channel[0];
        }
        std::copy(channel, channel + 4, rgba->begin() + p * 4);
    }
    return rgba;
}

// alphaMode and alphaCutoff: how the base colour's alpha covers the surface.
void readAlpha(GltfContext& context, const tinygltf::Material& m, const std::string& where, Material& material) {
    if (m.alphaMode == "MASK") {
        material.alphaMode = AlphaMode::Mask;
    } else if (m.alphaMode == "BLEND") {
        material.alphaMode = AlphaMode::Blend;
    } else if (m.alphaMode != "OPAQUE") {
        context.fail(where + ": alphaMode '" + m.alphaMode + "' is not OPAQUE, MASK or BLEND");
    }
    if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.0)
        context.fail(where + ": alphaCutoff must be a finite number of at least 0");
    material.alphaCutoff = static_cast<float>(m.alphaCutoff);
}

// Texture `index` of the file: its image, decoded (textureSlot checked that it did) unless another texture
// decoded it already (`decoded`, by image: loadGltfImage counted one copy of each), and its sampler.
Texture convertTexture(const GltfContext& context, int index,
                       std::map<int, std::shared_ptr<const std::vector<uint8_t>>>& decoded) {
    const tinygltf::Model& model = context.model;
    const tinygltf::Texture& gltfTexture = model.textures[index];
    Texture texture;
    texture.name = gltfTexture.name;
    const int source = imageSource(gltfTexture);
    const tinygltf::Image& image = model.images[source];
    std::shared_ptr<const std::vector<uint8_t>>& rgba = decoded[source];
    if (!rgba) rgba = decodeImage(context, image, source);
    texture.width = image.width;
    texture.height = image.height;
    texture.rgba = rgba;
    if (gltfTexture.sampler >= 0) {
        if (gltfTexture.sampler >= static_cast<int>(model.samplers.size())) {
            context.fail(describe("texture", index, gltfTexture.name) + " refers to sampler " +
                         std::to_string(gltfTexture.sampler) + ", which does not exist");
        }
        const tinygltf::Sampler& sampler = model.samplers[gltfTexture.sampler];
        texture.wrapS = wrapMode(sampler.wrapS);
        texture.wrapT = wrapMode(sampler.wrapT);
        texture.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        readMinFilter(sampler.minFilter, texture);
    }
    return texture;
}

}  // namespace

void convertTextures(GltfContext& context) {
    Scene& scene = context.scene;
    // The textures some slot reads, in the file's order: the others would only take memory and time.
    std::map<int, int> sceneIndex;  // by glTF texture, its index in scene.textures (set below)
    std::map<int, std::shared_ptr<const std::vector<uint8_t>>> decoded;  // by image
    for (const Material& material : scene.materials) {
        for (const TextureSlot* slot : material.textureSlots())
            if (slot->used()) sceneIndex[slot->texture] = 0;
    }
    for (auto& [gltfIndex, index] : sceneIndex) {
        index = static_cast<int>(scene.textures.size());
        scene.textures.push_back(convertTexture(context, gltfIndex, decoded));
    }
    for (Material& material : scene.materials) {
        for (TextureSlot* slot : material.textureSlots())
            if (slot->used()) slot->texture = sceneIndex.at(slot->texture);
    }
}

void convertMaterials(GltfContext& context) {
    const tinygltf::Model& model = context.model;
    // Rays carry the volumes they are inside as 16-bit material indices (shaders/media.h), 0xffff meaning
    // none; the default material may take one more index.
    if (model.materials.size() + 1 >= VKRT_NO_MEDIUM) {
        context.fail("has " + std::to_string(model.materials.size()) + " materials; vkrt supports at most " +
                     std::to_string(VKRT_NO_MEDIUM - 2));
    }
    for (size_t i = 0; i < model.materials.size(); ++i) {
        const tinygltf::Material& m = model.materials[i];
        const std::string where = describe("material", static_cast<int>(i), m.name);
        Material material;
        material.name = m.name;
        // A material no node places is checked as the others are, but its texture slots are left empty: their
        // images were not decoded (a file's unused materials took their images' memory on both devices).
        context.readTextures =
            !context.placedMaterials || context.placedMaterials->count(static_cast<int>(i)) != 0;
        // Core metallic-roughness factors and the base colour texture.
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() != 4 || !allFinite(pbr.baseColorFactor)) {
            context.fail(where + ": baseColorFactor must be 4 finite numbers");
        }
        material.baseColor = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                                       pbr.baseColorFactor[3]);
        material.baseColorTexture =
            textureSlot(context, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                        pbr.baseColorTexture.extensions, where + " base colour texture");
        material.metallicRoughnessTexture =
            textureSlot(context, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                        pbr.metallicRoughnessTexture.extensions, where + " metallic-roughness texture");
        material.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
        material.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
        if (m.emissiveFactor.size() != 3 || !allFinite(m.emissiveFactor)) {
            context.fail(where + ": emissiveFactor must be 3 finite numbers");
        }
        material.doubleSided = m.doubleSided;

        // Transmission, ior, volume and emissive strength from the extensions.
        const float strength = readMaterialExtensions(context, m.extensions, where, material);
        // KHR_materials_ior: ior 0 stands for infinity, i.e. a perfect mirror; 1e6 is close enough (a Fresnel
        // reflectance within 4e-6 of 1), and so it is for any larger index, whose square overflows single
        // precision beyond about 1.8e19 (the GPU's samples came out NaN there).
        if (material.ior == 0.0f || material.ior > 1e6f) material.ior = 1e6f;
        if (strength < 0.0f) context.fail(where + ": emissiveStrength must not be negative");
        // Each factor is within single precision (gltf_schema.cpp), but their product need not be: an
        // infinite emission made the GPU drop every sample it reached and the CPU write infinite pixels.
        const glm::dvec3 emission =
            glm::max(glm::dvec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]),
                     glm::dvec3(0.0)) *
            static_cast<double>(strength);
        if (std::max({emission.x, emission.y, emission.z}) > std::numeric_limits<float>::max())
            context.fail(where +
                         ": emissiveFactor times emissiveStrength is beyond single precision (3.4e38)");
        material.emission = glm::vec3(emission);
        readSpecular(context, m.extensions, where, material);
        readExtensionTextures(context, m.extensions, where, material);
        readUnlit(m.extensions, material);
        readClearcoat(context, m.extensions, where, material);
        readSheen(context, m.extensions, where, material);
        material.emissiveTexture = textureSlot(context, m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                               m.emissiveTexture.extensions, where + " emissive texture");
        material.occlusionTexture =
            textureSlot(context, m.occlusionTexture.index, m.occlusionTexture.texCoord,
                        m.occlusionTexture.extensions, where + " occlusion texture");
        if (!std::isfinite(m.occlusionTexture.strength))
            context.fail(where + ": occlusion strength is not finite");
        material.occlusionStrength = static_cast<float>(std::clamp(m.occlusionTexture.strength, 0.0, 1.0));
        material.normalTexture = textureSlot(context, m.normalTexture.index, m.normalTexture.texCoord,
                                             m.normalTexture.extensions, where + " normal texture");
        if (!std::isfinite(m.normalTexture.scale)) context.fail(where + ": normal texture scale is not finite");
        material.normalScale = normalScaleOf(m.normalTexture.scale);
        // One tangent frame a vertex (Material::tangentFrameSlot): the coat's normal texture is mapped with
        // the base's texture coordinates' frame, as the Khronos sample viewer maps it.
        if (material.normalTexture.used() && material.clearcoatNormalTexture.used()) {
            if (material.normalTexture.texCoord != material.clearcoatNormalTexture.texCoord) {
                context.warn(where + ": the normal texture reads TEXCOORD_" +
                             std::to_string(material.normalTexture.texCoord) +
                             " and the clearcoat normal texture TEXCOORD_" +
                             std::to_string(material.clearcoatNormalTexture.texCoord) +
                             "; vkrt maps both with the tangent frame of the first");
            } else if (!material.clearcoatNormalTexture.turnsAs(material.normalTexture)) {
                context.warn(where +
                             ": KHR_texture_transform turns, mirrors or stretches the normal texture and the "
                             "clearcoat normal texture differently; vkrt maps both with the tangent frame of "
                             "the first");
            }
        }
        readAlpha(context, m, where, material);
        context.scene.materials.push_back(material);
    }
    context.readTextures = true;
}

uint32_t defaultMaterial(GltfContext& context) {
    if (context.defaultMaterial < 0) {
        context.defaultMaterial = static_cast<int>(context.scene.materials.size());
        Material material;  // glTF's default material: white, metallic 1, roughness 1
        material.name = "default";
        context.scene.materials.push_back(material);
    }
    return static_cast<uint32_t>(context.defaultMaterial);
}

}  // namespace vkrt
