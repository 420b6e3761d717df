// The GPU layouts of a BVH: the binary tree as 32-byte nodes with the primitive order of the leaves (what
// the CPU reference walks), and the 4-wide tree of 64-byte quantized nodes the GPU walks (shaders/shared.h).
#pragma once

#include <vector>

#include "bvh/bvh.h"
#include "shared.h"

namespace vkrt {

struct FlatBvh {
    std::vector<gpu::BvhNode> nodes;
    std::vector<uint32_t> primIndices;
    bool empty() const { return primIndices.empty(); }
};

// The one flatten step from build-time nodes to the binary layout. The builder already places children in
// pairs, so node indices carry over unchanged.
FlatBvh flatten(const Bvh& bvh);

// The binary tree collapsed into 4-wide nodes (shared.h's WideBvhNode): each wide node takes a binary
// node's children and opens the largest (by surface area) interior one among them until it has four.
// Leaves keep their primitive ranges, so primitives stay in the binary tree's leaf order. Nodes are in
// depth-first order, the root first; a tree without primitives is one node with four empty slots.
std::vector<gpu::WideBvhNode> collapseToWide(const FlatBvh& bvh);

// A wide node's child slot decoded as the GPU decodes it: its box (float, with the GPU's flushing of
// denormal results to zero), or empty() for an unused slot.
Aabb wideChildBounds(const gpu::WideBvhNode& node, int slot);
uint32_t wideChildLink(const gpu::WideBvhNode& node, int slot);

}  // namespace vkrt
