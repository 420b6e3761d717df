// Emissive triangles as area lights, picked in proportion to their power and sampled uniformly by area.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

struct AreaLightSample {
    uint32_t triangle = 0;
    glm::dvec3 point{0.0};
    double u = 0.0, v = 0.0;  // barycentric weights of the triangle's v1 and v2 at `point`
    glm::dvec3 normal{0.0};   // the emitting (front) side
    double pdfArea = 0.0;     // probability density of this point per unit area, light choice included
};

class AreaLights {
  public:
    explicit AreaLights(const Scene& scene);
    bool empty() const { return triangles_.empty(); }

    // `pick` chooses the triangle, (u, v) the point on it; all three in [0, 1).
    AreaLightSample sample(double pick, double u, double v) const;

    // The tables behind sample(), for the GPU: emissive triangles, cumulative power (ending at 1) and the
    // area density of each triangle's points.
    const std::vector<uint32_t>& triangles() const { return triangles_; }
    const std::vector<double>& cdf() const { return cdf_; }
    const std::vector<double>& pdfArea() const { return pdfArea_; }

  private:
    const Scene& scene_;
    std::vector<uint32_t> triangles_;
    std::vector<double> cdf_;      // cumulative power, normalised to end at 1
    std::vector<double> pdfArea_;  // per triangle: pick probability / area
};

}  // namespace vkrt
