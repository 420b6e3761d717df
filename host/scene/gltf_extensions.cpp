#include "scene/gltf_extensions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "common/memory_need.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_transforms.h"

namespace vkrt {
namespace {

constexpr std::array<const char*, 18> kSupportedExtensions = {"KHR_materials_specular",
                                                              "KHR_texture_transform",
                                                              "EXT_texture_webp",
                                                              "KHR_materials_emissive_strength",
                                                              "KHR_materials_transmission",
                                                              "KHR_materials_ior",
                                                              "KHR_materials_volume",
                                                              "KHR_materials_unlit",
                                                              "KHR_materials_clearcoat",
                                                              "KHR_materials_sheen",
                                                              "KHR_lights_punctual",
                                                              "EXT_mesh_gpu_instancing",
                                                              "KHR_mesh_quantization",
                                                              "EXT_meshopt_compression",
                                                              "KHR_draco_mesh_compression",
                                                              "VKRT_sphere",
                                                              "VKRT_shape",
                                                              "VKRT_csg"};

}  // namespace

bool isSupportedExtension(const std::string& name) {
    return std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), name) !=
           kSupportedExtensions.end();
}

void checkExtensions(GltfContext& context) {
    for (const std::string& name : context.model.extensionsRequired) {
        if (!isSupportedExtension(name))
            context.fail("requires extension " + name + ", which vkrt does not support");
    }
    for (const std::string& name : context.model.extensionsUsed) {
        if (!isSupportedExtension(name)) context.warn("ignoring optional extension " + name);
    }
}

std::optional<std::string> unsupportedRequiredExtension(const nlohmann::json& document) {
    if (!document.is_object() || !document.contains("extensionsRequired") ||
        !document["extensionsRequired"].is_array()) {
        return std::nullopt;
    }
    for (const nlohmann::json& name : document["extensionsRequired"]) {
        if (name.is_string() && !isSupportedExtension(name.get<std::string>()))
            return name.get<std::string>();
    }
    return std::nullopt;
}

float readMaterialExtensions(const GltfContext& context, const tinygltf::ExtensionMap& extensions,
                             const std::string& where, Material& material) {
    float strength = 1.0f;
    for (const auto& [name, value] : extensions) {
        const std::string extWhere = where + " " + name;
        if (!value.IsObject()) context.fail(extWhere + " must be a JSON object");
        if (name == "KHR_materials_emissive_strength") {
            strength = static_cast<float>(jsonNumber(context, value, "emissiveStrength", 1.0, extWhere));
        } else if (name == "KHR_materials_transmission") {
            material.transmission = static_cast<float>(
                std::clamp(jsonNumber(context, value, "transmissionFactor", 0.0, extWhere), 0.0, 1.0));
        } else if (name == "KHR_materials_ior") {
            material.ior = static_cast<float>(jsonNumber(context, value, "ior", 1.5, extWhere));
            if (material.ior != 0.0f && material.ior < 1.0f)
                context.fail(extWhere + ": ior must be 0 or at least 1");
        } else if (name == "KHR_materials_volume") {
            material.thickness = static_cast<float>(
                std::max(0.0, jsonNumber(context, value, "thicknessFactor", 0.0, extWhere)));
            const double distance = jsonNumber(context, value, "attenuationDistance",
                                               std::numeric_limits<double>::infinity(), extWhere);
            if (!(distance > 0.0)) context.fail(extWhere + ": attenuationDistance must be positive");
            // A distance below float's smallest absorbs all light over any path, as that smallest does (1e-50
            // rounded to 0 and was refused as not positive).
            material.attenuationDistance =
                std::max(static_cast<float>(distance), std::numeric_limits<float>::denorm_min());
            material.attenuationColor =
                jsonVector3(context, value, "attenuationColor", glm::vec3(1.0f), extWhere);
        }
    }
    return strength;
}

// One translation / rotation / scale per instance, applied before the node's own transform (instance
// transforms are in the node's local space).
std::vector<glm::dmat4> instanceTransforms(
    const GltfContext& context, const tinygltf::Value& extension, const std::string& where,
    const std::function<void(uint64_t bytes, const std::string& what)>& checkHeld) {
    const std::string extWhere = where + " EXT_mesh_gpu_instancing";
    if (!extension.IsObject() || !extension.Has("attributes") || !extension.Get("attributes").IsObject()) {
        context.fail(extWhere + " needs an 'attributes' object");
    }
    // Read the attribute accessors, which must agree on the instance count. Each is counted before it is
    // read, as the floats kept beside those read before and the doubles the reader builds them from.
    const tinygltf::Value& attributes = extension.Get("attributes");
    std::vector<float> translation, rotation, scale;
    size_t count = 0;
    bool any = false;
    double attributeBytes = 0.0;  // the floats of the attributes read so far
    auto read = [&](const char* name, int components, std::vector<float>& out) {
        if (!attributes.Has(name)) return;
        if (!attributes.Get(name).IsInt())
            context.fail(extWhere + ": attribute " + name + " must be an accessor index");
        const int accessor = attributes.Get(name).GetNumberAsInt();
        const std::string what = extWhere + " " + name;
        const double values = static_cast<double>(context.accessors.count(accessor, what)) * components;
        checkHeld(saturatedBytes(attributeBytes + values * (sizeof(float) + sizeof(double))), what);
        out = context.accessors.readFloats(accessor, components, what);
        attributeBytes += values * sizeof(float);
        const size_t n = out.size() / components;
        if (any && n != count) context.fail(extWhere + ": attributes have different counts");
        count = n;
        any = true;
        for (float v : out) {
            if (!std::isfinite(v)) context.fail(extWhere + " " + name + " has a non-finite value");
        }
    };
    read("TRANSLATION", 3, translation);
    read("ROTATION", 4, rotation);
    read("SCALE", 3, scale);
    if (!any) context.fail(extWhere + " has no TRANSLATION, ROTATION or SCALE attribute");
    // Compose each instance's TRS, with glTF's defaults for absent attributes.
    checkHeld(saturatedBytes(attributeBytes + static_cast<double>(count) * sizeof(glm::dmat4)),
              extWhere + "'s " + std::to_string(count) + " instance transforms");
    std::vector<glm::dmat4> transforms(count);
    for (size_t i = 0; i < count; ++i) {
        glm::dvec3 t(0.0), s(1.0);
        glm::dquat r(1.0, 0.0, 0.0, 0.0);
        if (!translation.empty()) t = {translation[3 * i], translation[3 * i + 1], translation[3 * i + 2]};
        if (!rotation.empty()) {
            glm::dquat q(rotation[4 * i + 3], rotation[4 * i], rotation[4 * i + 1], rotation[4 * i + 2]);
            const double length = glm::length(q);
            if (!(length > 0.0))
                context.fail(extWhere + ": instance " + std::to_string(i) +
                             " has a zero rotation quaternion");
            r = q / length;
        }
        if (!scale.empty()) s = {scale[3 * i], scale[3 * i + 1], scale[3 * i + 2]};
        transforms[i] = trsMatrix(t, r, s);
    }
    return transforms;
}

void addLight(GltfContext& context, const tinygltf::Value& extension, const glm::dmat4& world,
              const std::string& where) {
    if (!extension.IsObject() || !extension.Has("light") || !extension.Get("light").IsInt()) {
        context.fail(where + ": KHR_lights_punctual must name a light by index");
    }
    const int index = extension.Get("light").GetNumberAsInt();
    if (index < 0 || index >= static_cast<int>(context.model.lights.size())) {
        context.fail(where + " refers to light " + std::to_string(index) + ", which does not exist");
    }
    const tinygltf::Light& source = context.model.lights[index];
    const std::string lightWhere = describe("light", index, source.name);
    PunctualLight light;
    light.name = source.name;
    if (source.type == "point")
        light.type = LightType::Point;
    else if (source.type == "spot")
        light.type = LightType::Spot;
    else if (source.type == "directional")
        light.type = LightType::Directional;
    else
        context.fail(lightWhere + " has unknown type '" + source.type + "'");
    if (!source.color.empty()) {
        if (source.color.size() != 3 || !allFinite(source.color))
            context.fail(lightWhere + ": color must be 3 numbers");
        light.color = glm::vec3(source.color[0], source.color[1], source.color[2]);
    }
    if (!std::isfinite(source.intensity) || source.intensity < 0.0)
        context.fail(lightWhere + ": intensity must be >= 0");
    light.intensity = static_cast<float>(source.intensity);
    // Each is within single precision, but what the shaders multiply need not be (a point light of colour
    // 1e30 and intensity 1e30 made the GPU drop its samples and the CPU write infinite pixels).
    if (std::max({light.color.x, light.color.y, light.color.z}) * source.intensity >
        std::numeric_limits<float>::max())
        context.fail(lightWhere + ": color times intensity is beyond single precision (3.4e38)");
    light.range = static_cast<float>(std::max(0.0, source.range));
    light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
    light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
    if (light.type == LightType::Spot &&
        !(light.innerConeAngle >= 0.0f && light.innerConeAngle < light.outerConeAngle &&
          light.outerConeAngle <= static_cast<float>(M_PI / 2))) {
        context.fail(lightWhere + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
    }
    // The light sits at the node's origin and shines down its -Z.
    light.position = glm::dvec3(world[3]);
    light.direction = glm::normalize(glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0));
    context.scene.lights.push_back(light);
}

// A sphere of `radius` around the node's origin, placed by the node's transform, which must scale
// uniformly.
Sphere placeSphere(GltfContext& context, const tinygltf::Value& extension, const glm::dmat4& world,
                   const std::string& where) {
    const std::string sphereWhere = where + " VKRT_sphere";
    if (!extension.IsObject()) context.fail(sphereWhere + " must be an object");
    const double radius = jsonNumber(context, extension, "radius", -1.0, sphereWhere);
    if (!(radius > 0.0) || !std::isfinite(radius))
        context.fail(sphereWhere + ": radius must be a finite number > 0");
    uint32_t material = 0;
    if (!extension.Has("material")) {
        material = defaultMaterial(context);
    } else {
        const tinygltf::Value& value = extension.Get("material");
        if (!value.IsInt() || value.GetNumberAsInt() < 0 ||
            value.GetNumberAsInt() >= static_cast<int>(context.model.materials.size())) {
            context.fail(sphereWhere + ": material must be the index of a material");
        }
        material = static_cast<uint32_t>(value.GetNumberAsInt());
    }
    // The node's scale along its three axes must agree to 1e-4.
    const glm::dmat3 linear(world);
    const double sx = glm::length(linear[0]), sy = glm::length(linear[1]), sz = glm::length(linear[2]);
    const double scale = (sx + sy + sz) / 3.0;
    if (scale == 0.0)
        return {glm::vec3(world[3]), 0.0f, material};  // hidden by its node (the caller decides)
    if (!(scale > 0.0) || std::abs(sx - scale) > 1e-4 * scale || std::abs(sy - scale) > 1e-4 * scale ||
        std::abs(sz - scale) > 1e-4 * scale) {
        context.fail(sphereWhere + ": the node transform must scale uniformly (a sphere stays a sphere)");
    }
    // Finite in single precision, as the scene holds it (a centre of 1e40 became infinite there).
    const glm::dvec3 center(world[3]);
    const glm::vec3 stored(center);
    const double worldRadius = radius * scale;
    if (!std::isfinite(stored.x + stored.y + stored.z) || !(worldRadius < 1e30)) {
        context.fail(sphereWhere + ": the placed sphere is not finite in single precision");
    }
    return {glm::vec3(center), static_cast<float>(worldRadius), material};
}

void readCameraExtras(GltfContext& context, const tinygltf::Value& extras, const std::string& where,
                      Camera& camera) {
    // extras belong to every application: a key of vkrt's that holds no number was written by another tool
    // for its own use ("aperture": "f/2.8"), and is passed over with a warning. A number is vkrt's to check.
    auto read = [&](const char* key) {
        if (!extras.IsObject() || !extras.Has(key)) return 0.0;
        if (!extras.Get(key).IsNumber()) {
            context.warn(where + ": extras." + key + " is not a number; it is ignored");
            return 0.0;
        }
        return jsonNumber(context, extras, key, 0.0, where + " extras");
    };
    camera.aperture = read("aperture");
    camera.focusDistance = read("focusDistance");
    if (camera.aperture < 0.0 || camera.focusDistance < 0.0)
        context.fail(where + ": aperture and focusDistance must be >= 0");
}

}  // namespace vkrt
