// Building scenes in code (tests, tools): flat-shaded triangles and the derived fields every loader fills.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

// Appends a triangle with flat normals (the geometric one) and zero texture coordinates.
void addFlatTriangle(Scene& scene, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, uint32_t material);

// Appends two triangles over a quad given in counter-clockwise order seen from its front.
void addFlatQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t material);

// The bounds of canonical shape `type` (shape_geometry.h's VKRT_SHAPE_*) placed by `toWorld`.
Aabb shapeBounds(uint32_t type, const glm::mat4& toWorld);

// A shape (VKRT_shape) of type `type` (shape_geometry.h's VKRT_SHAPE_*) placed by `toWorld`, which must be
// invertible.
Shape makeShape(uint32_t type, uint32_t material, const glm::dmat4& toWorld);

// The truth table of a solid of `count` shapes (Solid::table): bit s is inside(s), for s < 2^count, where s's
// set bits are the shapes a point is inside.
std::array<uint32_t, 8> truthTable(uint32_t count, const std::function<bool(uint32_t)>& inside);

// Appends a solid of `shapes` (at most VKRT_CSG_MAX_SHAPES; static, no motion) whose inside is `inside`: bit s
// of the truth table, for s < 2^shapes.size(), says whether points inside exactly the shapes of s's set bits are
// inside the solid. One shape with inside = {2} is the shape itself. The solid's bounds are its shapes' union.
void addSolid(Scene& scene, const std::vector<Shape>& shapes, const std::array<uint32_t, 8>& inside);

// Removes exact duplicates: triangles with the same corners in the same winding (any rotation) as an earlier
// one, whatever their materials. A duplicate can never be seen (it ties with its twin, and the smaller index
// wins), so it must not light the scene either (an emissive one behind its twin was among the lights) or
// filter shadow rays; and a stack of them makes every ray through it visit every copy. Back-to-back faces
// (the reverse winding) are other surfaces and stay. Returns how many were removed.
size_t removeDuplicateTriangles(Scene& scene);

// Removes duplicates (with a warning), then recomputes what derives from the triangles and materials:
// bounds and the list of emissive triangles.
void finalizeScene(Scene& scene);

}  // namespace vkrt
