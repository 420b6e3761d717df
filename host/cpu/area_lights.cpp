#include "cpu/area_lights.h"

#include <algorithm>
#include <cmath>

#include "cpu/optics.h"
#include "cpu/sphere_intersection.h"

namespace vkrt {

namespace {

double triangleArea(const Triangle& t) {
    return 0.5 *
           glm::length(glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0)));
}

double luminance(const glm::vec3& e) {
    return 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
}

// 1 - cos(theta_max) of the cone a sphere subtends from a point at distance^2 `distance2` from its centre,
// written as sin^2 / (1 + cos) to keep its digits for small, distant spheres.
double coneOneMinusCos(double radius, double distance2) {
    const double sin2Max = radius * radius / distance2;
    return sin2Max / (1.0 + std::sqrt(std::max(0.0, 1.0 - sin2Max)));
}

}  // namespace

AreaLights::AreaLights(const Scene& scene) : scene_(scene) {
    std::vector<double> power, area;
    auto add = [&](uint32_t primitive, double a) {
        const double p =
            a * std::max(luminance(scene.materials[scene.materialOf(primitive)].emission), 1e-12);
        if (!(a > 0.0) || !std::isfinite(p)) return;
        primitives_.push_back(primitive);
        power.push_back(p);
        area.push_back(a);
    };
    for (uint32_t index : scene.emissiveTriangles) {
        add(index, triangleArea(scene.triangles[index]));
    }
    for (uint32_t index : scene.emissiveSpheres) {
        const double r = scene.spheres[index].radius;
        add(static_cast<uint32_t>(scene.triangles.size()) + index, 4.0 * M_PI * r * r);
    }
    double total = 0.0;
    for (double p : power) total += p;
    totalPower_ = total;
    double running = 0.0;
    for (size_t i = 0; i < power.size(); ++i) {
        running += power[i];
        cdf_.push_back(running / total);
        pick_.push_back(power[i] / total);
        pdfArea_.push_back(power[i] / total / area[i]);
    }
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

AreaLightSample AreaLights::sample(double pick, double u, double v, const glm::dvec3& from,
                                   double time) const {
    const size_t i =
        std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), pick) - cdf_.begin(), cdf_.size() - 1);
    AreaLightSample s;
    s.primitive = primitives_[i];
    if (!scene_.isSphere(s.primitive)) {
        const Triangle t = scene_.triangleAt(s.primitive, time);
        // Uniform point on a triangle (Shirley and Chiu's square-root mapping).
        const double root = std::sqrt(u);
        const double b0 = 1.0 - root, b1 = root * (1.0 - v), b2 = root * v;
        s.point = b0 * glm::dvec3(t.v0) + b1 * glm::dvec3(t.v1) + b2 * glm::dvec3(t.v2);
        s.u = b1;
        s.v = b2;
        s.normal = glm::normalize(
            glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0)));
        s.pdfArea = pick_[i] / triangleArea(t);  // the area now (animations may scale it)
        return s;
    }
    const Sphere sphere = scene_.sphereAt(s.primitive, time);
    const glm::dvec3 center(sphere.center);
    const double radius = sphere.radius;
    const glm::dvec3 toCenter = center - from;
    const double distance2 = glm::dot(toCenter, toCenter);
    const double phi = 2.0 * M_PI * v;
    double oneMinusCosMax = 0.0;  // of the cone the sphere subtends
    if (distance2 <= radius * radius) {
        // Inside: uniform by area.
        const double z = 1.0 - 2.0 * u, ring = std::sqrt(std::max(0.0, 1.0 - z * z));
        s.normal = glm::dvec3(ring * std::cos(phi), ring * std::sin(phi), z);
        s.pdfArea = pick_[i] / (4.0 * M_PI * radius * radius);
    } else {
        // Uniform in the cone of directions the sphere subtends (pbrt-v4, Sphere::Sample). 1 - cos(theta_max)
        // is written as sin^2 / (1 + cos), which keeps its digits for small, distant spheres.
        const double distance = std::sqrt(distance2);
        const glm::dvec3 axis = toCenter / distance;
        const double sin2Max = radius * radius / distance2;
        const double sinMax = std::sqrt(sin2Max);
        oneMinusCosMax = coneOneMinusCos(radius, distance2);
        const double oneMinusCos = u * oneMinusCosMax;
        const double cosTheta = 1.0 - oneMinusCos;
        const double sin2Theta = oneMinusCos * (2.0 - oneMinusCos);
        // The angle at the centre between the axis (reversed) and the sampled point.
        const double cosAlpha =
            sin2Theta / sinMax + cosTheta * std::sqrt(std::max(0.0, 1.0 - sin2Theta / sin2Max));
        const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
        glm::dvec3 b1, b2;
        orthonormalBasis(axis, b1, b2);
        s.normal = -(sinAlpha * std::cos(phi) * b1 + sinAlpha * std::sin(phi) * b2 + cosAlpha * axis);
        s.pdfArea = 0.0;
    }
    s.point = center + radius * s.normal;
    const glm::dvec2 uv = sphereUv(s.normal);
    s.u = uv.x;
    s.v = uv.y;
    if (oneMinusCosMax > 0.0) {
        // The cone's solid-angle density 1 / (2 pi (1 - cos theta_max)), per unit area at the point.
        const glm::dvec3 offset = s.point - from;
        const double d2 = glm::dot(offset, offset);
        const double cosLight = std::max(0.0, -glm::dot(s.normal, offset) / std::sqrt(d2));
        s.pdfArea = pick_[i] * cosLight / (2.0 * M_PI * oneMinusCosMax * d2);
    }
    return s;
}

double AreaLights::solidAnglePdf(uint32_t primitive, const glm::dvec3& from, const glm::dvec3& point,
                                 double cosLight, double time) const {
    if (empty() || !(cosLight > 0.0)) return 0.0;
    const Material& material = scene_.materials[scene_.materialOf(primitive)];
    // Power is luminance times area (at the shutter's opening): the pick probability is that share of the
    // total; the point is then uniform over the primitive as it is at `time`.
    const double luminanceShare = std::max(luminance(material.emission), 1e-12) / totalPower_;
    const glm::dvec3 offset = point - from;
    const double distance2 = glm::dot(offset, offset);
    if (scene_.isSphere(primitive)) {
        const double openRadius = scene_.sphereOf(primitive).radius;
        const double pick = luminanceShare * 4.0 * M_PI * openRadius * openRadius;
        const Sphere sphere = scene_.sphereAt(primitive, time);
        const double radius = sphere.radius;
        const glm::dvec3 toCenter = glm::dvec3(sphere.center) - from;
        const double centerDistance2 = glm::dot(toCenter, toCenter);
        if (centerDistance2 > radius * radius)
            return pick / (2.0 * M_PI * coneOneMinusCos(radius, centerDistance2));
        return pick / (4.0 * M_PI * radius * radius) * distance2 / cosLight;
    }
    const double pick = luminanceShare * triangleArea(scene_.triangles[primitive]);
    return pick / triangleArea(scene_.triangleAt(primitive, time)) * distance2 / cosLight;
}

}  // namespace vkrt
