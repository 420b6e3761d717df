// glTF 2.0 (.gltf and .glb) to Scene: the node graph is walked, every primitive is flattened to world-space
// triangles, and bad input stops with a SceneError naming the file and the problem.
#pragma once

#include <string>

#include "scene/scene.h"

namespace vkrt {

// Extensions vkrt understands; a required extension outside this list is an error, an optional one a
// warning.
bool isSupportedExtension(const std::string& name);

Scene loadGltf(const std::string& path);

}  // namespace vkrt
