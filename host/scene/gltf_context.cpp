#include "scene/gltf_context.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

namespace vkrt {

std::string describe(const char* kind, int index, const std::string& name) {
    std::string s = std::string(kind) + " " + std::to_string(index);
    if (!name.empty()) s += " ('" + name + "')";
    return s;
}

bool allFinite(const std::vector<double>& values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

double jsonNumber(const GltfContext& context, const tinygltf::Value& object, const char* key, double fallback,
                  const std::string& where) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    if (!value.IsNumber()) context.fail(where + ": '" + key + "' must be a number");
    double v = value.GetNumberAsDouble();
    if (!std::isfinite(v)) context.fail(where + ": '" + key + "' is not finite");
    return v;
}

glm::vec2 jsonVector2(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec2 fallback, const std::string& where) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    if (!value.IsArray() || value.ArrayLen() != 2)
        context.fail(where + ": '" + key + "' must be an array of 2 numbers");
    glm::vec2 v;
    for (int c = 0; c < 2; ++c) {
        if (!value.Get(c).IsNumber()) context.fail(where + ": '" + key + "' must be an array of 2 numbers");
        v[c] = static_cast<float>(value.Get(c).GetNumberAsDouble());
        if (!std::isfinite(v[c])) context.fail(where + ": '" + key + "' is not finite");
    }
    return v;
}

glm::vec3 jsonVector3(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec3 fallback, const std::string& where) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    if (!value.IsArray() || value.ArrayLen() != 3)
        context.fail(where + ": '" + key + "' must be an array of 3 numbers");
    glm::vec3 v;
    for (int c = 0; c < 3; ++c) {
        if (!value.Get(c).IsNumber()) context.fail(where + ": '" + key + "' must be an array of 3 numbers");
        v[c] = static_cast<float>(value.Get(c).GetNumberAsDouble());
    }
    return v;
}

}  // namespace vkrt
