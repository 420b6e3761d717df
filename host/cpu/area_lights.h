// Emissive triangles and spheres as area lights, picked in proportion to their power. A triangle is sampled
// uniformly by area; a sphere by solid angle, uniformly inside the cone it subtends from the shading point
// (uniformly by area when the point is inside it).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

struct AreaLightSample {
    uint32_t primitive = 0;
    glm::dvec3 point{0.0};
    double u = 0.0, v = 0.0;  // triangles: barycentric weights of v1 and v2; spheres: texture coordinates
    glm::dvec3 normal{0.0};   // the emitting (front, outward) side
    double pdfArea = 0.0;     // probability density of this point per unit area, light choice included
};

class AreaLights {
  public:
    explicit AreaLights(const Scene& scene);
    bool empty() const { return primitives_.empty(); }

    // `pick` chooses the light, (u, v) the point on it; all three in [0, 1). `from` is the shading point.
    // `time` is the shutter time in [0, 1] (motion blur).
    AreaLightSample sample(double pick, double u, double v, const glm::dvec3& from, double time = 0.0) const;

    // The density per unit solid angle, seen from `from`, with which sample() picks `point` on emissive
    // `primitive` (cosLight: the cosine between the light's normal and the direction to `from`). Multiple
    // importance sampling weighs traced rays that hit a light with it.
    double solidAnglePdf(uint32_t primitive, const glm::dvec3& from, const glm::dvec3& point, double cosLight,
                         double time = 0.0) const;
    double totalPower() const { return totalPower_; }

    // The tables behind sample(), for the GPU: emissive primitives, cumulative power (ending at 1), each
    // one's pick probability and the area density of its points (pick probability / area).
    const std::vector<uint32_t>& primitives() const { return primitives_; }
    const std::vector<double>& cdf() const { return cdf_; }
    const std::vector<double>& pick() const { return pick_; }
    const std::vector<double>& pdfArea() const { return pdfArea_; }

  private:
    const Scene& scene_;
    std::vector<uint32_t> primitives_;
    std::vector<double> cdf_;
    std::vector<double> pick_;
    std::vector<double> pdfArea_;
    double totalPower_ = 0.0;
};

}  // namespace vkrt
