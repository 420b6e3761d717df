#include "scene/gltf_material_extensions.h"

#include <algorithm>

#include <tiny_gltf.h>

#include "scene/gltf_texture_slots.h"

namespace vkrt {

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

void readExtensionTextures(GltfContext& context, const tinygltf::ExtensionMap& extensions,
                           const std::string& where, Material& material) {
    if (const auto it = extensions.find("KHR_materials_transmission");
        it != extensions.end() && it->second.Has("transmissionTexture")) {
        material.transmissionTexture = textureSlot(context, it->second.Get("transmissionTexture"),
                                                   where + " KHR_materials_transmission transmissionTexture");
    }
    // KHR_materials_volume's thicknessTexture is not read: gltf_schema.cpp checks that its texture exists,
    // and its image is not decoded, so one that does not decode (or a KTX2 image alone) fails nothing.
}

void readClearcoat(GltfContext& context, const tinygltf::ExtensionMap& extensions, const std::string& where,
                   Material& material) {
    const auto it = extensions.find("KHR_materials_clearcoat");
    if (it == extensions.end()) return;
    const std::string extWhere = where + " KHR_materials_clearcoat";
    const tinygltf::Value& value = it->second;
    if (!value.IsObject()) context.fail(extWhere + " must be a JSON object");
    material.clearcoat =
        static_cast<float>(std::clamp(jsonNumber(context, value, "clearcoatFactor", 0.0, extWhere), 0.0, 1.0));
    material.clearcoatRoughness = static_cast<float>(
        std::clamp(jsonNumber(context, value, "clearcoatRoughnessFactor", 0.0, extWhere), 0.0, 1.0));
    if (value.Has("clearcoatTexture"))
        material.clearcoatTexture = textureSlot(context, value.Get("clearcoatTexture"), extWhere + " clearcoatTexture");
    if (value.Has("clearcoatRoughnessTexture")) {
        material.clearcoatRoughnessTexture =
            textureSlot(context, value.Get("clearcoatRoughnessTexture"), extWhere + " clearcoatRoughnessTexture");
    }
    if (value.Has("clearcoatNormalTexture")) {
        const tinygltf::Value& info = value.Get("clearcoatNormalTexture");
        material.clearcoatNormalTexture = textureSlot(context, info, extWhere + " clearcoatNormalTexture");
        material.clearcoatNormalScale =
            normalScaleOf(jsonNumber(context, info, "scale", 1.0, extWhere + " clearcoatNormalTexture"));
    }
}

void readSheen(GltfContext& context, const tinygltf::ExtensionMap& extensions, const std::string& where,
               Material& material) {
    const auto it = extensions.find("KHR_materials_sheen");
    if (it == extensions.end()) return;
    const std::string extWhere = where + " KHR_materials_sheen";
    const tinygltf::Value& value = it->second;
    if (!value.IsObject()) context.fail(extWhere + " must be a JSON object");
    material.sheenColor = glm::clamp(jsonVector3(context, value, "sheenColorFactor", glm::vec3(0.0f), extWhere),
                                     glm::vec3(0.0f), glm::vec3(1.0f));
    material.sheenRoughness =
        static_cast<float>(std::clamp(jsonNumber(context, value, "sheenRoughnessFactor", 0.0, extWhere), 0.0, 1.0));
    if (value.Has("sheenColorTexture"))
        material.sheenColorTexture = textureSlot(context, value.Get("sheenColorTexture"), extWhere + " sheenColorTexture");
    if (value.Has("sheenRoughnessTexture")) {
        material.sheenRoughnessTexture =
            textureSlot(context, value.Get("sheenRoughnessTexture"), extWhere + " sheenRoughnessTexture");
    }
}

void readUnlit(const tinygltf::ExtensionMap& extensions, Material& material) {
    material.unlit = extensions.count("KHR_materials_unlit") > 0;
}

}  // namespace vkrt
