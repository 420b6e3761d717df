// Ray-sphere intersection in double precision for the reference renderer, in the numerically careful form
// of Haines, Guenther and Akenine-Moller, "Precision Improvements for Ray/Sphere Intersection" (Ray
// Tracing Gems, ch. 7, 2019): the discriminant from the distance between the centre and the ray's closest
// approach (no b^2 - 4ac cancellation) and the near root from Vieta's formula (no -b + sqrt cancellation).
// shaders/sphere.glsl is the same test in single precision.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

// Both roots of |origin + t direction - centre| = radius, nearer first; false if the line misses.
inline bool sphereRoots(const glm::dvec3& center, double radius, const glm::dvec3& origin,
                        const glm::dvec3& direction, double& t0, double& t1) {
    const glm::dvec3 f = origin - center;
    const double a = glm::dot(direction, direction);
    const double halfB = -glm::dot(f, direction);  // -b / 2
    // (b/2)^2 - ac = a (r^2 - |l|^2), l the centre's offset from the line (RTG eq. 7.5).
    const glm::dvec3 l = f + (halfB / a) * direction;
    const double discriminant = a * (radius * radius - glm::dot(l, l));
    if (!(discriminant >= 0.0)) return false;
    const double c = glm::dot(f, f) - radius * radius;
    const double q = halfB + std::copysign(std::sqrt(discriminant), halfB);
    t0 = q != 0.0 ? c / q : 0.0;
    t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    return true;
}

// The nearest root in (tMin, tMax); false if there is none.
inline bool intersectSphere(const glm::dvec3& center, double radius, const glm::dvec3& origin,
                            const glm::dvec3& direction, double tMin, double tMax, double& t) {
    double t0, t1;
    if (!sphereRoots(center, radius, origin, direction, t0, t1)) return false;
    if (t0 > tMin && t0 < tMax) {
        t = t0;
        return true;
    }
    if (t1 > tMin && t1 < tMax) {
        t = t1;
        return true;
    }
    return false;
}

inline bool intersectSphere(const Sphere& sphere, const glm::dvec3& origin, const glm::dvec3& direction,
                            double tMin, double tMax, double& t) {
    return intersectSphere(glm::dvec3(sphere.center), sphere.radius, origin, direction, tMin, tMax, t);
}

// Texture coordinates of the point on a sphere with outward unit normal n (+Y up, as in glTF): u is the
// longitude, 0.5 facing +Z, v runs from 0 at the north pole to 1 at the south pole.
inline glm::dvec2 sphereUv(const glm::dvec3& n) {
    return {0.5 + std::atan2(n.x, n.z) / (2.0 * M_PI), std::acos(std::clamp(n.y, -1.0, 1.0)) / M_PI};
}

}  // namespace vkrt
