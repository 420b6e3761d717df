// glTF cameras, placed by the node that holds them.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "scene/gltf_context.h"

namespace vkrt {

// Appends camera `cameraIndex` placed by `world`, the transform of node `nodeIndex`; named after the camera,
// else its node, else its index.
void addCamera(GltfContext& context, int cameraIndex, const glm::dmat4& world, int nodeIndex,
               const std::string& nodeName);

}  // namespace vkrt
