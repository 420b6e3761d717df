// Ray-triangle intersection in double precision for the reference renderer (Moller and Trumbore, "Fast,
// Minimum Storage Ray/Triangle Intersection", 1997). The float vertices convert to double exactly, so the
// test is as accurate as double arithmetic allows; edges and vertices count as inside.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

struct TriangleHit {
    double t;
    double u, v;  // barycentric weights of v1 and v2
};

inline bool intersectTriangle(const Triangle& triangle, const glm::dvec3& origin, const glm::dvec3& direction,
                              double tMin, double tMax, TriangleHit& hit) {
    const glm::dvec3 v0(triangle.v0), edge1 = glm::dvec3(triangle.v1) - v0,
                                      edge2 = glm::dvec3(triangle.v2) - v0;
    const glm::dvec3 p = glm::cross(direction, edge2);
    const double determinant = glm::dot(edge1, p);
    if (determinant == 0.0 || !std::isfinite(determinant)) return false;  // parallel to the plane
    const double inverse = 1.0 / determinant;
    const glm::dvec3 s = origin - v0;
    const double u = glm::dot(s, p) * inverse;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, edge1);
    const double v = glm::dot(direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(edge2, q) * inverse;
    if (!(t > tMin && t < tMax)) return false;
    hit = {t, u, v};
    return true;
}

}  // namespace vkrt
