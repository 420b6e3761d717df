#include "scene/gltf_materials.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "media.h"
#include "scene/gltf_extensions.h"

namespace vkrt {
namespace {

WrapMode wrapMode(int mode) {
    if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::ClampToEdge;
    if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::MirroredRepeat;
    return WrapMode::Repeat;
}

// Expand the image's 1 to 4 channels of 8 or 16 bits to 8-bit RGBA.
void decodeImage(const GltfContext& context, const tinygltf::Image& image, int imageIndex, Texture& texture) {
    if (image.image.empty() || image.width <= 0 || image.height <= 0 || image.component < 1 ||
        image.component > 4 || (image.bits != 8 && image.bits != 16)) {
        return;
    }
    texture.width = image.width;
    texture.height = image.height;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    const size_t bytesPerChannel = image.bits / 8;
    if (image.image.size() < pixels * image.component * bytesPerChannel) {
        context.fail(describe("image", imageIndex, image.uri) + " has fewer pixels than its size");
    }
    texture.rgba.resize(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
        uint8_t channel[4] = {0, 0, 0, 255};
        for (int c = 0; c < image.component; ++c) {
            // 16-bit images keep their high byte (little-endian storage, as tinygltf decodes).
            size_t at = (p * image.component + c) * bytesPerChannel + (bytesPerChannel - 1);
            channel[c] = image.image[at];
        }
        if (image.component <= 2) {  // grey or grey + alpha
            channel[3] = image.component == 2 ? channel[1] : 255;
            channel[1] = channel[2] = channel[0];
        }
        std::copy(channel, channel + 4, texture.rgba.begin() + p * 4);
    }
}

// The scene texture a material slot refers to (-1 for none); a texture whose image is missing fails here.
int textureIndex(const GltfContext& context, int gltfTexture, const std::string& where) {
    const tinygltf::Model& model = context.model;
    if (gltfTexture < 0) return -1;
    if (gltfTexture >= static_cast<int>(context.scene.textures.size())) {
        context.fail(where + " refers to texture " + std::to_string(gltfTexture) + ", which does not exist");
    }
    const tinygltf::Texture& texture = model.textures[gltfTexture];
    if (context.scene.textures[gltfTexture].rgba.empty()) {
        std::string image = "its image";
        if (texture.source >= 0 && texture.source < static_cast<int>(model.images.size())) {
            const tinygltf::Image& img = model.images[texture.source];
            image = describe("image", texture.source, img.uri.empty() ? img.name : img.uri);
        }
        context.fail(where + " uses texture " + std::to_string(gltfTexture) + " but " + image +
                     " is missing or could not be decoded");
    }
    return gltfTexture;
}

// KHR_texture_transform on a texture slot.
void readTextureTransform(GltfContext& context, const tinygltf::Value& transform, const std::string& where,
                          TextureSlot& slot) {
    const std::string extWhere = where + " KHR_texture_transform";
    if (!transform.IsObject()) context.fail(extWhere + " must be a JSON object");
    slot.offset = jsonVector2(context, transform, "offset", glm::vec2(0.0f), extWhere);
    slot.rotation = static_cast<float>(jsonNumber(context, transform, "rotation", 0.0, extWhere));
    slot.scale = jsonVector2(context, transform, "scale", glm::vec2(1.0f), extWhere);
    slot.texCoord = static_cast<int>(jsonNumber(context, transform, "texCoord", slot.texCoord, extWhere));
}

void warnAboutTexCoord(GltfContext& context, TextureSlot& slot, const std::string& where) {
    if (slot.used() && (slot.texCoord < 0 || slot.texCoord > 1)) {
        context.warn(where + " uses TEXCOORD_" + std::to_string(slot.texCoord) +
                     "; vkrt reads TEXCOORD_0 and TEXCOORD_1, and reads TEXCOORD_0 for it");
        slot.texCoord = 0;
    }
}

// A material's texture slot: the texture, its texture coordinate set and its KHR_texture_transform.
TextureSlot textureSlot(GltfContext& context, int index, int texCoord,
                        const tinygltf::ExtensionMap& extensions, const std::string& where) {
    TextureSlot slot;
    slot.texture = textureIndex(context, index, where);
    slot.texCoord = texCoord;
    if (!slot.used()) return slot;
    if (auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
        readTextureTransform(context, it->second, where, slot);
    }
    warnAboutTexCoord(context, slot, where);
    return slot;
}

// The same from a textureInfo object inside an extension (tinygltf leaves those as JSON values).
TextureSlot textureSlot(GltfContext& context, const tinygltf::Value& info, const std::string& where) {
    TextureSlot slot;
    if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) {
        context.fail(where + " must be an object with an integer 'index'");
    }
    slot.texture = textureIndex(context, info.Get("index").GetNumberAsInt(), where);
    slot.texCoord = static_cast<int>(jsonNumber(context, info, "texCoord", 0.0, where));
    if (info.Has("extensions") && info.Get("extensions").Has("KHR_texture_transform")) {
        readTextureTransform(context, info.Get("extensions").Get("KHR_texture_transform"), where, slot);
    }
    warnAboutTexCoord(context, slot, where);
    return slot;
}

// KHR_materials_specular: the dielectric's specular reflection, scaled and tinted.
void readSpecular(GltfContext& context, const tinygltf::ExtensionMap& extensions, const std::string& where,
                  Material& material) {
    const auto it = extensions.find("KHR_materials_specular");
    if (it == extensions.end()) return;
    const std::string extWhere = where + " KHR_materials_specular";
    const tinygltf::Value& value = it->second;
    if (!value.IsObject()) context.fail(extWhere + " must be a JSON object");
    material.specularFactor =
        static_cast<float>(std::clamp(jsonNumber(context, value, "specularFactor", 1.0, extWhere), 0.0, 1.0));
    material.specularColor = glm::max(
        jsonVector3(context, value, "specularColorFactor", glm::vec3(1.0f), extWhere), glm::vec3(0.0f));
    if (value.Has("specularTexture"))
        material.specularTexture =
            textureSlot(context, value.Get("specularTexture"), extWhere + " specularTexture");
    if (value.Has("specularColorTexture")) {
        material.specularColorTexture =
            textureSlot(context, value.Get("specularColorTexture"), extWhere + " specularColorTexture");
    }
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

}  // namespace

void convertTextures(GltfContext& context) {
    const tinygltf::Model& model = context.model;
    for (size_t i = 0; i < model.textures.size(); ++i) {
        const tinygltf::Texture& gltfTexture = model.textures[i];
        Texture texture;
        texture.name = gltfTexture.name;
        if (gltfTexture.source < 0 || gltfTexture.source >= static_cast<int>(model.images.size())) {
            // Textures without a core image source (e.g. only KHR_texture_basisu) stay empty; using one
            // fails.
            context.scene.textures.push_back(texture);
            continue;
        }
        decodeImage(context, model.images[gltfTexture.source], gltfTexture.source, texture);
        if (gltfTexture.sampler >= 0) {
            if (gltfTexture.sampler >= static_cast<int>(model.samplers.size())) {
                context.fail(describe("texture", static_cast<int>(i), gltfTexture.name) +
                             " refers to sampler " + std::to_string(gltfTexture.sampler) +
                             ", which does not exist");
            }
            const tinygltf::Sampler& sampler = model.samplers[gltfTexture.sampler];
            texture.wrapS = wrapMode(sampler.wrapS);
            texture.wrapT = wrapMode(sampler.wrapT);
            texture.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        context.scene.textures.push_back(std::move(texture));
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
        glm::vec3 emissive(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
        material.doubleSided = m.doubleSided;

        // Transmission, ior, volume and emissive strength from the extensions.
        const float strength = readMaterialExtensions(context, m.extensions, where, material);
        // KHR_materials_ior: ior 0 stands for infinity, i.e. a perfect mirror; 1e6 is close enough.
        if (material.ior == 0.0f) material.ior = 1e6f;
        if (strength < 0.0f) context.fail(where + ": emissiveStrength must not be negative");
        material.emission = glm::max(emissive, glm::vec3(0.0f)) * strength;
        readSpecular(context, m.extensions, where, material);
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
        material.normalScale = static_cast<float>(m.normalTexture.scale);
        readAlpha(context, m, where, material);
        context.scene.materials.push_back(material);
    }
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
