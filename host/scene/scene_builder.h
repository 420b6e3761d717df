// Building scenes in code (tests, tools): flat-shaded triangles and the derived fields every loader fills.
#pragma once

#include "scene/scene.h"

namespace vkrt {

// Appends a triangle with flat normals (the geometric one) and zero texture coordinates.
void addFlatTriangle(Scene& scene, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, uint32_t material);

// Appends two triangles over a quad given in counter-clockwise order seen from its front.
void addFlatQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t material);

// Removes exact duplicates: triangles with the same corners in the same winding (any rotation) and the
// same material as an earlier one. A duplicate can never be seen (it ties with its twin), but a stack of
// them makes every ray through it visit every copy. Returns how many were removed.
size_t removeDuplicateTriangles(Scene& scene);

// Removes duplicates (with a warning), then recomputes what derives from the triangles and materials:
// bounds and the list of emissive triangles.
void finalizeScene(Scene& scene);

}  // namespace vkrt
