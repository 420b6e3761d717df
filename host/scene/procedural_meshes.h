// Procedural triangle meshes for tests and benchmarks.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

// A UV sphere of 2 * rings * segments triangles (poles included as thin triangles).
std::vector<Triangle> makeUvSphere(glm::vec3 center, float radius, int rings, int segments,
                                   uint32_t material = 0);

// `count` triangles with random positions and sizes inside a unit cube (deterministic for a seed).
std::vector<Triangle> makeTriangleSoup(size_t count, uint32_t seed, float size = 0.05f,
                                       uint32_t material = 0);

}  // namespace vkrt
