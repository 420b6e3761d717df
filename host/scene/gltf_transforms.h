// Node transforms: the one translation-rotation-scale composition that static nodes, animated nodes and
// EXT_mesh_gpu_instancing instances all use, and a node's local matrix at rest or at a time.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace vkrt {

struct GltfContext;
class NodeAnimations;

// T * R * S (glTF 2.0 section 3.5.3): scale first, then rotate, then translate. `rotation` must be unit
// length.
glm::dmat4 trsMatrix(const glm::dvec3& translation, const glm::dquat& rotation, const glm::dvec3& scale);

// The node's local transform from its matrix or its TRS values, each checked for size and finiteness.
glm::dmat4 localTransform(const GltfContext& context, int nodeIndex);

// The node's local transform at `time` of the animation timeline (its rest transform when not animated).
glm::dmat4 localTransformAt(const GltfContext& context, const NodeAnimations& animations, int nodeIndex,
                            double time);

}  // namespace vkrt
