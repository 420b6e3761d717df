// KHR_lights_punctual: irradiance that a point, spot or directional light delivers to a point.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

struct LightArrival {
    glm::dvec3 toLight{0.0};     // unit vector from the shaded point towards the light
    double distance = 0.0;       // infinity for directional lights
    glm::dvec3 irradiance{0.0};  // on a surface facing the light (multiply by the cosine), in lux
};

// Irradiance as the KHR_lights_punctual spec defines it: intensity / d^2 for point and spot lights
// (candela), with the spec's smooth range window and spot cone falloff; lux for directional lights.
inline LightArrival arriveFrom(const PunctualLight& light, const glm::dvec3& point) {
    LightArrival arrival;
    const glm::dvec3 radiantColor = glm::dvec3(light.color) * static_cast<double>(light.intensity);
    if (light.type == LightType::Directional) {
        arrival.toLight = -light.direction;
        arrival.distance = std::numeric_limits<double>::infinity();
        arrival.irradiance = radiantColor;
        return arrival;
    }
    const glm::dvec3 offset = light.position - point;
    const double distance2 = glm::dot(offset, offset);
    arrival.distance = std::sqrt(distance2);
    if (!(arrival.distance > 0.0)) return arrival;
    arrival.toLight = offset / arrival.distance;
    double attenuation = 1.0 / distance2;
    if (light.range > 0.0f) {
        const double ratio = arrival.distance / light.range;
        attenuation *= std::clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    }
    if (light.type == LightType::Spot) {
        const double cosOuter = std::cos(static_cast<double>(light.outerConeAngle));
        const double cosInner = std::cos(static_cast<double>(light.innerConeAngle));
        const double scale = 1.0 / std::max(0.001, cosInner - cosOuter);
        const double cd = glm::dot(light.direction, -arrival.toLight);
        const double falloff = std::clamp((cd - cosOuter) * scale, 0.0, 1.0);
        attenuation *= falloff * falloff;
    }
    arrival.irradiance = radiantColor * attenuation;
    return arrival;
}

}  // namespace vkrt
