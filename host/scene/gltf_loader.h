// glTF 2.0 (.gltf and .glb) to Scene: the node graph is walked, every primitive is flattened to world-space
// triangles, and bad input stops with a SceneError naming the file and the problem.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "scene/scene.h"

namespace vkrt {

// Extensions vkrt understands; a required extension outside this list is an error, an optional one a
// warning.
bool isSupportedExtension(const std::string& name);

struct LoadOptions {
    // Motion blur: the shutter interval in the file's animation time (seconds); when absent, the scene's
    // extras {"shutter": [open, close]}, else closed at 0 (no motion).
    std::optional<std::array<double, 2>> shutter;
    // The animation that plays: its index or its name; empty, the first (a file's animations are clips, as an
    // idle, a walk and a run on the same joints, and played together they mixed; vkrt says which plays where
    // there are several).
    std::string animation;
    // The host memory the placed triangles may take: a file whose nodes and instances place more (counted
    // from its accessors, before any is placed) is refused with a MemoryError naming the figures.
    uint64_t maxSceneBytes = UINT64_MAX;
    std::string memorySource = "unlimited";  // where maxSceneBytes comes from, for that error
};

Scene loadGltf(const std::string& path, const LoadOptions& options = {});

}  // namespace vkrt
