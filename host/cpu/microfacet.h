// The GGX (Trowbridge-Reitz) microfacet distribution for glossy reflection and rough refraction: Walter et
// al., "Microfacet Models for Refraction through Rough Surfaces" (EGSR 2007), with Heitz's height-correlated
// masking-shadowing ("Understanding the Masking-Shadowing Function", JCGT 3(2), 2014) and visible-normal
// sampling ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018). Directions are in a local
// frame whose z axis is the shading normal; shaders/microfacet.glsl is the same in single precision.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace vkrt {

// Roughness below this is a perfect mirror (glTF roughness 0); above it alpha = roughness^2, at least the
// square of this, so the distribution stays finite.
inline constexpr double kMirrorRoughness = 1e-3;

inline double ggxAlpha(double roughness) {
    return std::max(roughness * roughness, kMirrorRoughness * kMirrorRoughness);
}

// D(h): microfacet normals per unit solid angle and unit projected area.
inline double ggxD(double cosH, double alpha) {
    if (cosH <= 0.0) return 0.0;
    const double a2 = alpha * alpha;
    const double d = cosH * cosH * (a2 - 1.0) + 1.0;
    return a2 / (M_PI * d * d);
}

// Smith's Lambda for a direction at cosine `cosTheta` from the normal.
inline double ggxLambda(double cosTheta, double alpha) {
    const double c2 = cosTheta * cosTheta;
    if (c2 >= 1.0) return 0.0;
    const double tan2 = (1.0 - c2) / c2;
    return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
}

inline double ggxG1(double cosTheta, double alpha) {
    return 1.0 / (1.0 + ggxLambda(cosTheta, alpha));
}

// Height-correlated masking and shadowing of the pair (viewer, light).
inline double ggxG2(double cosOut, double cosIn, double alpha) {
    return 1.0 / (1.0 + ggxLambda(cosOut, alpha) + ggxLambda(cosIn, alpha));
}

// A microfacet normal visible from `toViewer` (local, z up), distributed as D_v(h) = G1 max(0, v.h) D / v.z.
inline glm::dvec3 sampleGgxVisibleNormal(const glm::dvec3& toViewer, double alpha, double u1, double u2) {
    // Stretch the view direction onto the hemisphere configuration.
    const glm::dvec3 vh = glm::normalize(glm::dvec3(alpha * toViewer.x, alpha * toViewer.y, toViewer.z));
    const double lengthSquared = vh.x * vh.x + vh.y * vh.y;
    const glm::dvec3 t1 = lengthSquared > 0.0 ? glm::dvec3(-vh.y, vh.x, 0.0) / std::sqrt(lengthSquared)
                                              : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 t2 = glm::cross(vh, t1);
    // A point on the projected disk, warped towards the visible half.
    const double r = std::sqrt(u1), phi = 2.0 * M_PI * u2;
    const double p1 = r * std::cos(phi);
    const double s = 0.5 * (1.0 + vh.z);
    const double p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * r * std::sin(phi);
    const glm::dvec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    // Unstretch.
    return glm::normalize(glm::dvec3(alpha * nh.x, alpha * nh.y, std::max(0.0, nh.z)));
}

// Density of a reflected direction when its half vector h was drawn by sampleGgxVisibleNormal:
// D_v(h) / (4 v.h) = G1(v) D(h) / (4 v.z).
inline double ggxReflectionPdf(double cosOut, double cosH, double alpha) {
    if (cosOut <= 0.0) return 0.0;
    return ggxG1(cosOut, alpha) * ggxD(cosH, alpha) / (4.0 * cosOut);
}

// The power heuristic (Veach 1997) for `count` samples of density `pdf` against one of density `other`.
inline double powerHeuristic(double count, double pdf, double other) {
    const double a = count * pdf;
    const double sum = a * a + other * other;
    return sum > 0.0 ? a * a / sum : 0.0;
}

}  // namespace vkrt
