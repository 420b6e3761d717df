// How a glTF metallic-roughness material shades in vkrt's distributed Whitted model (docs/materials.md
// explains the choices): Lambert diffuse lit by the lights; a GGX specular lobe lit by the lights and, where
// it can show the scene, traced (a mirror ray at roughness 0, a ray sampled from the visible normals above);
// refraction through the same microfacet normal, weighted by Fresnel.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "cpu/microfacet.h"
#include "cpu/optics.h"
#include "scene/scene.h"

namespace vkrt {

struct SurfaceResponse {
    glm::dvec3 albedo{1.0};     // base colour (factor times texture), linear
    glm::dvec3 diffuse{0.0};    // Lambert reflectance: albedo * (1 - metallic) * (1 - transmission)
    glm::dvec3 specular{0.0};   // F0: of the dielectric, or the base colour for metals
    double alpha = 1.0;         // GGX width, roughness^2
    bool mirror = false;        // roughness 0: the lobe is a delta (exact mirror and refraction)
    bool traced = false;        // the specular lobe is traced (metals, transmission, roughness < 1)
    double transmission = 0.0;  // (1 - metallic) * transmission
    double metallic = 0.0;
    double ior = 1.5;
};

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
    s.alpha = ggxAlpha(material.roughness);
    s.mirror = material.roughness < kMirrorRoughness;
    // A matte opaque dielectric (roughness 1, glTF's default) keeps its faint sheen to the lights and the
    // ambient term: tracing a ray per hit for it would double the cost of every diffuse scene.
    s.traced = s.metallic > 0.0 || s.transmission > 0.0 || material.roughness < 1.0;
    return s;
}

// Fresnel reflectance at a microfacet seen at cosine cosH; eta relative across the interface.
inline glm::dvec3 fresnelAt(const SurfaceResponse& s, double cosH, double eta) {
    return (1.0 - s.metallic) * glm::dvec3(fresnelDielectric(cosH, eta)) +
           s.metallic * fresnelSchlick(s.albedo, cosH);
}

// The specular lobe for light from `toLight`: F D G2 / (4 cos_o cos_i); zero for a mirror (a delta lobe
// meets a light of zero size with probability zero, and area lights reach mirrors through traced rays).
inline glm::dvec3 specularBrdf(const SurfaceResponse& s, const glm::dvec3& normal, const glm::dvec3& toViewer,
                               const glm::dvec3& toLight) {
    const double cosOut = glm::dot(normal, toViewer), cosIn = glm::dot(normal, toLight);
    if (s.mirror || cosOut <= 0.0 || cosIn <= 0.0) return glm::dvec3(0.0);
    const glm::dvec3 halfway = glm::normalize(toViewer + toLight);
    return fresnelAt(s, glm::dot(toViewer, halfway), s.ior) * ggxD(glm::dot(normal, halfway), s.alpha) *
           ggxG2(cosOut, cosIn, s.alpha) / (4.0 * cosOut * cosIn);
}

// Density with which the traced lobe would have chosen `toLight` (0 when it is not traced).
inline double lobePdf(const SurfaceResponse& s, const glm::dvec3& normal, const glm::dvec3& toViewer,
                      const glm::dvec3& toLight) {
    if (!s.traced || s.mirror) return 0.0;
    const glm::dvec3 halfway = glm::normalize(toViewer + toLight);
    return ggxReflectionPdf(glm::dot(normal, toViewer), glm::dot(normal, halfway), s.alpha);
}

}  // namespace vkrt
