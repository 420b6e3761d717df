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
    // vkrt keeps a scene's numbers in single precision (as gltf_schema.cpp checks the file's own).
    if (std::abs(v) >= 0x1.ffffffp+127)
        context.fail(where + ": '" + key + "' is beyond single precision's range");
    return v;
}

namespace {

// `count` finite numbers from the array object[key] into `out`; false when the key is absent.
bool jsonFloats(const GltfContext& context, const tinygltf::Value& object, const char* key, int count,
                float* out, const std::string& where) {
    if (!object.IsObject() || !object.Has(key)) return false;
    const tinygltf::Value& value = object.Get(key);
    const std::string expected =
        where + ": '" + key + "' must be an array of " + std::to_string(count) + " numbers";
    if (!value.IsArray() || static_cast<int>(value.ArrayLen()) != count) context.fail(expected);
    for (int c = 0; c < count; ++c) {
        if (!value.Get(c).IsNumber()) context.fail(expected);
        out[c] = static_cast<float>(value.Get(c).GetNumberAsDouble());
        if (!std::isfinite(out[c])) context.fail(where + ": '" + key + "' is not finite");
    }
    return true;
}

}  // namespace

glm::vec2 jsonVector2(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec2 fallback, const std::string& where) {
    glm::vec2 v;
    return jsonFloats(context, object, key, 2, &v.x, where) ? v : fallback;
}

glm::vec3 jsonVector3(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec3 fallback, const std::string& where) {
    glm::vec3 v;
    return jsonFloats(context, object, key, 3, &v.x, where) ? v : fallback;
}

}  // namespace vkrt
