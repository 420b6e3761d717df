#include "scene/gltf_texture_slots.h"

#include <tiny_gltf.h>

#include "scene/gltf_images.h"

namespace vkrt {
namespace {

// The scene texture a material slot refers to (-1 for none); a texture whose image is missing fails here.
int textureIndex(const GltfContext& context, int gltfTexture, const std::string& where) {
    const tinygltf::Model& model = context.model;
    if (gltfTexture < 0) return -1;
    if (gltfTexture >= static_cast<int>(context.scene.textures.size())) {
        context.fail(where + " refers to texture " + std::to_string(gltfTexture) + ", which does not exist");
    }
    const tinygltf::Texture& texture = model.textures[gltfTexture];
    if (context.scene.textures[gltfTexture].rgba.empty()) {
        const int source = imageSource(texture);
        if (source < 0 || source >= static_cast<int>(model.images.size())) {
            context.fail(where + " uses texture " + std::to_string(gltfTexture) +
                         ", which has no image vkrt reads");
        }
        const auto failure = context.imageFailures.find(source);
        context.fail(where + " uses texture " + std::to_string(gltfTexture) + " but " +
                     describeImage(model, source) +
                     (failure != context.imageFailures.end() ? " could not be decoded: " + failure->second
                                                             : " is missing or could not be decoded"));
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

}  // namespace

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

}  // namespace vkrt
