#include "cpu/area_lights.h"

#include <algorithm>
#include <cmath>

namespace vkrt {

AreaLights::AreaLights(const Scene& scene) : scene_(scene) {
    std::vector<double> power, area;
    for (uint32_t index : scene.emissiveTriangles) {
        const Triangle& t = scene.triangles[index];
        const double a = 0.5 * glm::length(glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0),
                                                      glm::dvec3(t.v2) - glm::dvec3(t.v0)));
        const glm::dvec3 e(scene.materials[t.material].emission);
        const double luminance = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
        const double p = a * std::max(luminance, 1e-12);
        if (!(a > 0.0) || !std::isfinite(p)) continue;
        triangles_.push_back(index);
        power.push_back(p);
        area.push_back(a);
    }
    double total = 0.0;
    for (double p : power) total += p;
    double running = 0.0;
    for (size_t i = 0; i < power.size(); ++i) {
        running += power[i];
        cdf_.push_back(running / total);
        pdfArea_.push_back(power[i] / total / area[i]);
    }
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

AreaLightSample AreaLights::sample(double pick, double u, double v) const {
    const size_t i =
        std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), pick) - cdf_.begin(), cdf_.size() - 1);
    const Triangle& t = scene_.triangles[triangles_[i]];
    // Uniform point on a triangle (Shirley and Chiu's square-root mapping).
    const double root = std::sqrt(u);
    const double b0 = 1.0 - root, b1 = root * (1.0 - v), b2 = root * v;
    AreaLightSample s;
    s.triangle = triangles_[i];
    s.point = b0 * glm::dvec3(t.v0) + b1 * glm::dvec3(t.v1) + b2 * glm::dvec3(t.v2);
    s.u = b1;
    s.v = b2;
    s.normal =
        glm::normalize(glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0)));
    s.pdfArea = pdfArea_[i];
    return s;
}

}  // namespace vkrt
