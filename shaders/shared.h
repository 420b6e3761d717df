// Every struct, binding index and size that the host and the shaders share. Included by C++ (which maps
// the GLSL types onto GLM) and by GLSL, so each layout has exactly one definition.
#ifndef VKRT_SHARED_H
#define VKRT_SHARED_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>
namespace vkrt::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uint = uint32_t;
#endif

// The deepest BVH the builder emits (levels, root included). The GPU traversal stack holds one entry per
// level below the root, so this bounds its size; the builder switches to median splits near the limit to
// guarantee it, whatever the input.
#define VKRT_BVH_MAX_DEPTH 64

// A flattened BVH node, 32 bytes (std430 packs a vec3 and a uint into 16 bytes).
// Interior node: primCount == 0, the children are nodes leftOrFirst and leftOrFirst + 1.
// Leaf: primCount > 0 primitives starting at leftOrFirst in the primitive index array.
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint primCount;
};

#ifdef __cplusplus
static_assert(sizeof(BvhNode) == 32, "BvhNode must stay 32 bytes");
static_assert(offsetof(BvhNode, leftOrFirst) == 12, "std430: uint packs after vec3");
static_assert(offsetof(BvhNode, boundsMax) == 16, "std430: vec3 aligns to 16 bytes");
static_assert(offsetof(BvhNode, primCount) == 28, "std430: uint packs after vec3");
}  // namespace vkrt::gpu
#endif

#endif  // VKRT_SHARED_H
