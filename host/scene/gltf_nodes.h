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

// Where the scene's detail is: per axis, the median of its parts' centres (each mesh primitive's by the
// median of its vertices, read from up to 4096 of them, in the box of its POSITION bounds; each sphere's and
// shape's box), placed by the node transforms (instancing ignored); the origin when there are none. A part
// more than 64 times the median part's size counts by the point of its box nearest the median of the others.
// Not the middle of all bounds: a ground sphere of radius 1e5 under a few small objects would pull the middle
// 5e4 away from them, and every position stored relative to it (in float on the GPU) would lose its low
// digits there; nor the median of centres alone, which for one object on a ground sphere is the ground's
// centre.
glm::dvec3 approximateCenter(const GltfContext& context, const std::vector<int>& roots);

}  // namespace vkrt
