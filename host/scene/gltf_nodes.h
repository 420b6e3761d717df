// The glTF node graph before the walk: which nodes are roots, that the graph is a forest, and roughly
// where the scene's geometry lies.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf_context.h"

namespace vkrt {

// The default scene's root nodes; without scenes, every node that is nobody's child.
std::vector<int> sceneRoots(const GltfContext& context);

// The node graph must be a forest: indices in range, no cycles, no node with two parents.
void checkNodeGraph(const GltfContext& context, const std::vector<int>& roots);

// The centre of the bounds that the POSITION accessors' min and max give, placed by the node transforms
// (instancing ignored); the origin when no accessor has bounds.
glm::dvec3 approximateCenter(const GltfContext& context, const std::vector<int>& roots);

}  // namespace vkrt
