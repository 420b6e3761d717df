// VKRT_shape and VKRT_csg (docs/vkrt_shape.md): analytic shapes, alone or combined by constructive solid
// geometry, as the scene's solids.
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf_context.h"

namespace tinygltf {
class Node;
}  // namespace tinygltf

namespace vkrt {

// A node's local transform at each pose time (the shutter's opening, then each motion segment's end).
using LocalPoses = std::function<std::vector<glm::dmat4>(int node)>;

// Whether the node carries VKRT_shape or VKRT_csg.
bool hasSolid(const tinygltf::Node& node);
// Whether the node is a CSG object, whose children are its operands rather than nodes of the scene.
bool isCsg(const tinygltf::Node& node);

// Adds the solid of node `nodeIndex`, placed by its world transform at each pose time (`poses`), to the
// scene; a CSG node's operands are placed below it by `localPoses`. Fails on a malformed or singular shape,
// an operand that is not a shape or a CSG node, or more than VKRT_CSG_MAX_SHAPES shapes in one object.
void addSolid(GltfContext& context, int nodeIndex, const std::vector<glm::dmat4>& poses,
              const LocalPoses& localPoses);

}  // namespace vkrt
