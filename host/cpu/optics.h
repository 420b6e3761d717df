// The optics of smooth surfaces: reflection, refraction by Snell's law and the Fresnel equations.
// Directions point away from the surface (pbrt's convention): `toViewer` points back along the arriving
// ray, and `normal` lies on the same side as `toViewer`.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace vkrt {

// Mirror direction of `toViewer` about `normal`.
inline glm::dvec3 reflect(const glm::dvec3& toViewer, const glm::dvec3& normal) {
    return 2.0 * glm::dot(toViewer, normal) * normal - toViewer;
}

// Refracts `toViewer` through a surface with relative index eta = n_transmitted / n_incident.
// Returns false on total internal reflection.
inline bool refract(const glm::dvec3& toViewer, const glm::dvec3& normal, double eta,
                    glm::dvec3& transmitted) {
    const double cosI = glm::dot(toViewer, normal);
    const double sin2I = std::max(0.0, 1.0 - cosI * cosI);
    const double sin2T = sin2I / (eta * eta);
    if (sin2T >= 1.0) return false;
    const double cosT = std::sqrt(1.0 - sin2T);
    transmitted = -toViewer / eta + (cosI / eta - cosT) * normal;
    return true;
}

// Unpolarised Fresnel reflectance of a dielectric interface (Born and Wolf): the mean of the s and p
// reflectances. cosI is the cosine on the incident side, eta = n_transmitted / n_incident. Returns 1 for
// total internal reflection.
inline double fresnelDielectric(double cosI, double eta) {
    cosI = std::clamp(cosI, 0.0, 1.0);
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// Schlick's approximation, used for metals whose F0 is their base colour.
inline glm::dvec3 fresnelSchlick(const glm::dvec3& f0, double cosI) {
    const double m = std::pow(1.0 - std::clamp(cosI, 0.0, 1.0), 5.0);
    return f0 + (glm::dvec3(1.0) - f0) * m;
}

// `v` turned by the smallest rotation that takes unit vector `from` to unit vector `to` (Rodrigues).
inline glm::dvec3 rotateLike(const glm::dvec3& v, const glm::dvec3& from, const glm::dvec3& to) {
    const glm::dvec3 axis = glm::cross(from, to);
    const double sine = glm::length(axis), cosine = glm::dot(from, to);
    if (!(sine > 1e-12) || cosine <= -1.0 + 1e-12) return cosine < 0.0 ? to : v;
    const glm::dvec3 k = axis / sine;
    return v * cosine + glm::cross(k, v) * sine + k * glm::dot(k, v) * (1.0 - cosine);
}

// An orthonormal basis with `n` as its third axis (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 6(1), 2017).
inline void orthonormalBasis(const glm::dvec3& n, glm::dvec3& b1, glm::dvec3& b2) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    b1 = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace vkrt
