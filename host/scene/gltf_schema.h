// The glTF document as JSON, checked before tinygltf reads it: tinygltf skips a property of the wrong type
// and carries on, so `"primitives": {}` would load as an empty mesh. Every property vkrt reads is checked
// here for its JSON type and range; unknown properties stay allowed.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace vkrt {

// The JSON text of a .gltf file's bytes, or a .glb's JSON chunk; none where a .glb has no readable one.
std::optional<std::string_view> gltfJsonText(std::string_view file, bool binary);

// The JSON of a .gltf file's bytes, or of a .glb's JSON chunk; a discarded value when there is none to parse
// (the loader then lets tinygltf say what is wrong).
nlohmann::json readGltfJson(std::string_view file, bool binary);

// A GLB file: the header, the JSON chunk and, unless `bin` is empty, the binary chunk.
std::string glbFile(const std::string& json, const std::string& bin);

// The GLB file `glb` (read from `path`) with its JSON chunk replaced by `json` (its binary chunk as it is).
std::string replaceGlbJson(std::string_view glb, const std::string& json, const std::string& path);

// Throws SceneError "path: meshes[0].primitives: expected an array" at the first property of the wrong type
// or out of its range, or an index that names nothing.
void validateGltfJson(const nlohmann::json& document, const std::string& path);

}  // namespace vkrt
