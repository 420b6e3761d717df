// How a glTF metallic-roughness material shades in vkrt's Whitted model (docs/materials.md explains the
// choices): Lambert diffuse plus a normalised Blinn-Phong highlight for lights, and traced mirror and
// refraction rays weighted by Fresnel.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

struct SurfaceResponse {
    glm::dvec3 albedo{1.0};     // base colour (factor times texture), linear
    glm::dvec3 diffuse{0.0};    // Lambert reflectance: albedo * (1 - metallic) * (1 - transmission)
    glm::dvec3 specular{0.0};   // highlight colour: F0 of the dielectric, or the base colour for metals
    double shininess = 0.0;     // Blinn-Phong exponent
    double mirror = 0.0;        // how much of the Fresnel reflectance is traced as a mirror ray
    double transmission = 0.0;  // (1 - metallic) * transmission
    double metallic = 0.0;
    double ior = 1.5;
};

// Blinn-Phong exponent with the same highlight width as a Beckmann lobe of roughness alpha = r^2
// (Walter et al., "Microfacet Models for Refraction through Rough Surfaces", 2007: n = 2 / alpha^2 - 2).
inline double blinnPhongExponent(double roughness) {
    const double alpha = std::max(roughness * roughness, 1e-3);
    return 2.0 / (alpha * alpha) - 2.0;
}

// Reflectance at normal incidence of a dielectric with index `ior` in air.
inline double dielectricF0(double ior) {
    const double r = (ior - 1.0) / (ior + 1.0);
    return r * r;
}

inline SurfaceResponse surfaceResponse(const Material& material, const glm::dvec3& albedo) {
    SurfaceResponse s;
    s.albedo = albedo;
    s.metallic = material.metallic;
    s.ior = material.ior;
    s.transmission = (1.0 - s.metallic) * material.transmission;
    s.diffuse = albedo * (1.0 - s.metallic) * (1.0 - material.transmission);
    s.specular = glm::mix(glm::dvec3(dielectricF0(material.ior)), albedo, s.metallic);
    s.shininess = blinnPhongExponent(material.roughness);
    const double gloss = 1.0 - material.roughness;
    s.mirror = gloss * gloss;
    return s;
}

// The reflected radiance per unit irradiance for light arriving from `toLight`: Lambert plus the
// energy-normalised Blinn-Phong lobe (n + 8) / (8 pi) cos^n(theta_h).
inline glm::dvec3 whittedBrdf(const SurfaceResponse& s, const glm::dvec3& normal, const glm::dvec3& toViewer,
                              const glm::dvec3& toLight) {
    const glm::dvec3 halfway = glm::normalize(toViewer + toLight);
    const double cosH = std::max(0.0, glm::dot(normal, halfway));
    const double lobe = (s.shininess + 8.0) / (8.0 * M_PI) * std::pow(cosH, s.shininess);
    return s.diffuse / M_PI + s.specular * lobe;
}

}  // namespace vkrt
