#include "scene/gltf_texture_slots.h"

#include <cstdint>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "scene/gltf_images.h"

namespace vkrt {
namespace {

// The glTF texture a material slot refers to (-1 for none, and for every slot of a material no node places);
// a texture whose image is missing fails here.
int textureIndex(const GltfContext& context, int gltfTexture, const std::string& where) {
    const tinygltf::Model& model = context.model;
    if (gltfTexture < 0) return -1;
    if (gltfTexture >= static_cast<int>(model.textures.size())) {
        context.fail(where + " refers to texture " + std::to_string(gltfTexture) + ", which does not exist");
    }
    const int source = imageSource(model.textures[gltfTexture]);
    if (source < 0 || source >= static_cast<int>(model.images.size())) {
        context.fail(where + " uses texture " + std::to_string(gltfTexture) +
                     ", which has no image vkrt reads");
    }
    if (!context.readTextures) return -1;  // a material no node places: its image was not decoded
    if (!holdsPixels(model.images[source])) {
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

std::optional<std::set<int>> placedMaterials(const nlohmann::json& document) {
    const auto array = [](const nlohmann::json& parent, const char* key) -> const nlohmann::json* {
        return parent.is_object() && parent.contains(key) && parent[key].is_array() ? &parent[key] : nullptr;
    };
    const auto indexIn = [](const nlohmann::json& parent, const char* key,
                            size_t count) -> std::optional<size_t> {
        if (!parent.is_object() || !parent.contains(key) || !parent[key].is_number_integer())
            return std::nullopt;
        const int64_t index = parent[key].get<int64_t>();
        if (index < 0 || static_cast<uint64_t>(index) >= count) return std::nullopt;
        return static_cast<size_t>(index);
    };
    static const nlohmann::json kNone = nlohmann::json::array();
    const nlohmann::json* nodes = array(document, "nodes");
    if (nodes == nullptr) nodes = &kNone;
    const nlohmann::json* meshes = array(document, "meshes");
    if (meshes == nullptr) meshes = &kNone;
    const size_t materialCount = array(document, "materials") ? document["materials"].size() : 0;

    // The roots as sceneRoots chooses them: the default scene's (else the first scene's), or with no scene
    // every node that is nobody's child.
    std::vector<size_t> pending;
    const auto addNodes = [&](const nlohmann::json& list) {
        for (const nlohmann::json& node : list) {
            if (!node.is_number_integer() || node.get<int64_t>() < 0 || node.get<uint64_t>() >= nodes->size())
                return false;
            pending.push_back(node.get<size_t>());
        }
        return true;
    };
    if (const nlohmann::json* scenes = array(document, "scenes"); scenes != nullptr && !scenes->empty()) {
        const std::optional<size_t> chosen = document.contains("scene")
                                                 ? indexIn(document, "scene", scenes->size())
                                                 : std::optional<size_t>(0);
        if (!chosen) return std::nullopt;
        if (const nlohmann::json* roots = array((*scenes)[*chosen], "nodes"); roots && !addNodes(*roots))
            return std::nullopt;
    } else {
        std::vector<bool> isChild(nodes->size(), false);
        for (const nlohmann::json& node : *nodes) {
            if (const nlohmann::json* children = array(node, "children")) {
                for (const nlohmann::json& child : *children)
                    if (child.is_number_integer() && child.get<int64_t>() >= 0 &&
                        child.get<uint64_t>() < nodes->size())
                        isChild[child.get<size_t>()] = true;
            }
        }
        for (size_t i = 0; i < nodes->size(); ++i)
            if (!isChild[i]) pending.push_back(i);
    }

    // Every node below them, once (a cycle is the converter's to refuse).
    std::set<int> placed;
    std::vector<bool> visited(nodes->size(), false);
    while (!pending.empty()) {
        const size_t nodeIndex = pending.back();
        pending.pop_back();
        if (visited[nodeIndex]) continue;
        visited[nodeIndex] = true;
        const nlohmann::json& node = (*nodes)[nodeIndex];
        if (const nlohmann::json* children = array(node, "children"); children && !addNodes(*children))
            return std::nullopt;
        if (const std::optional<size_t> mesh = indexIn(node, "mesh", meshes->size())) {
            if (const nlohmann::json* primitives = array((*meshes)[*mesh], "primitives")) {
                for (const nlohmann::json& primitive : *primitives)
                    if (const auto material = indexIn(primitive, "material", materialCount))
                        placed.insert(static_cast<int>(*material));
            }
        }
        if (node.is_object() && node.contains("extensions") && node["extensions"].is_object()) {
            for (const char* extension : {"VKRT_sphere", "VKRT_shape"}) {
                if (!node["extensions"].contains(extension)) continue;
                if (const auto material = indexIn(node["extensions"][extension], "material", materialCount))
                    placed.insert(static_cast<int>(*material));
            }
        }
    }
    return placed;
}

std::set<int> texturesReadByMaterials(const nlohmann::json& document,
                                      const std::optional<std::set<int>>& materials) {
    // The slots convertMaterials and the readers of gltf_material_extensions.h read: an image this leaves out
    // is not decoded, and a slot that reads it fails.
    static const std::pair<const char*, std::vector<const char*>> kExtensionSlots[] = {
        {"KHR_materials_specular", {"specularTexture", "specularColorTexture"}},
        {"KHR_materials_transmission", {"transmissionTexture"}},
        {"KHR_materials_clearcoat",
         {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"}},
        {"KHR_materials_sheen", {"sheenColorTexture", "sheenRoughnessTexture"}}};
    std::set<int> read;
    const auto add = [&read](const nlohmann::json& parent, const char* key) {
        if (!parent.is_object() || !parent.contains(key)) return;
        const nlohmann::json& info = parent[key];
        if (info.is_object() && info.contains("index") && info["index"].is_number_integer())
            read.insert(info["index"].get<int>());
    };
    if (!document.is_object() || !document.contains("materials") || !document["materials"].is_array())
        return read;
    const nlohmann::json& list = document["materials"];
    for (size_t i = 0; i < list.size(); ++i) {
        const nlohmann::json& material = list[i];
        if (!material.is_object() || (materials && materials->count(static_cast<int>(i)) == 0)) continue;
        if (material.contains("pbrMetallicRoughness")) {
            add(material["pbrMetallicRoughness"], "baseColorTexture");
            add(material["pbrMetallicRoughness"], "metallicRoughnessTexture");
        }
        for (const char* key : {"normalTexture", "occlusionTexture", "emissiveTexture"}) add(material, key);
        if (!material.contains("extensions") || !material["extensions"].is_object()) continue;
        const nlohmann::json& extensions = material["extensions"];
        for (const auto& [extension, keys] : kExtensionSlots) {
            if (!extensions.contains(extension)) continue;
            for (const char* key : keys) add(extensions[extension], key);
        }
    }
    return read;
}

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
