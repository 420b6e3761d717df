// What every step of the glTF conversion shares: the model, the file's path (for messages), the accessor
// reader and the scene being filled, with the small readers of JSON values that several steps use.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf_accessors.h"
#include "scene/scene.h"
#include "scene/scene_error.h"

namespace tinygltf {
class Model;
class Value;
}  // namespace tinygltf

namespace vkrt {

struct GltfContext {
    GltfContext(const tinygltf::Model& gltfModel, std::string filePath)
        : model(gltfModel), path(std::move(filePath)), accessors(model, path) {}

    // Bad input: one line naming the file and the problem.
    [[noreturn]] void fail(const std::string& message) const { throw SceneError(path + ": " + message); }
    void warn(const std::string& message) { scene.warnings.push_back(message); }

    const tinygltf::Model& model;
    std::string path;
    AccessorReader accessors;
    Scene scene;
    int defaultMaterial = -1;  // index of glTF's default material in scene.materials, once one needs it
    std::map<int, std::string> imageFailures;  // why images did not decode, by index (loadGltfImage)
    // The materials the scene's nodes place (placedMaterials), every one when nullopt: only their textures
    // are decoded and read.
    std::optional<std::set<int>> placedMaterials;
    bool readTextures = true;  // false while a material no node places is read: its texture slots stay empty
};

// "kind index ('name')", the way messages name a glTF object.
std::string describe(const char* kind, int index, const std::string& name);

bool allFinite(const std::vector<double>& values);

// object[key] as a finite number, or `fallback` when the object or key is absent.
double jsonNumber(const GltfContext& context, const tinygltf::Value& object, const char* key, double fallback,
                  const std::string& where);

// object[key] as an array of 3 numbers, or `fallback` when the object or key is absent.
glm::vec2 jsonVector2(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec2 fallback, const std::string& where);
glm::vec3 jsonVector3(const GltfContext& context, const tinygltf::Value& object, const char* key,
                      glm::vec3 fallback, const std::string& where);

}  // namespace vkrt
