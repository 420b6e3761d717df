// The optics of smooth surfaces: reflection, refraction by Snell's law, the Fresnel equations, and the small
// vector helpers they need. Directions point away from the surface (pbrt's convention): `toViewer` points
// back along the arriving ray, and `normal` lies on the same side as `toViewer`.
#ifndef VKRT_OPTICS_H
#define VKRT_OPTICS_H

#include "shading_language.h"

VKRT_SHADING_BEGIN

VKRT_FN real maxComponent(real3 v) { return max(v.x, max(v.y, v.z)); }

// A value given at a triangle's corners, at barycentric weights uv of corners 1 and 2. As corner 0 plus the
// differences, so that equal corners give their value exactly: weights summing to 1 in rounded arithmetic
// made a white vertex colour 0.99999994, and an alpha equal to its MASK cutoff fell below it.
VKRT_FN real2 barycentric(real2 a, real2 b, real2 c, real2 uv) { return a + uv.x * (b - a) + uv.y * (c - a); }
VKRT_FN real3 barycentric(real3 a, real3 b, real3 c, real2 uv) { return a + uv.x * (b - a) + uv.y * (c - a); }
VKRT_FN real4 barycentric(real4 a, real4 b, real4 c, real2 uv) { return a + uv.x * (b - a) + uv.y * (c - a); }

VKRT_FN real maxAbs(real3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

VKRT_FN bool allFinite(real3 v) {
    return !isnan(v.x) && !isnan(v.y) && !isnan(v.z) && !isinf(v.x) && !isinf(v.y) && !isinf(v.z);
}

// Mirror direction of `toViewer` about `normal`.
VKRT_FN real3 reflectAbout(real3 toViewer, real3 normal) { return 2.0 * dot(toViewer, normal) * normal - toViewer; }

// Refracts `toViewer` through a surface with relative index eta = n_transmitted / n_incident; false on total
// internal reflection.
VKRT_FN bool refractThrough(real3 toViewer, real3 normal, real eta, VKRT_OUT(real3) transmitted) {
    const real cosI = dot(toViewer, normal);
    // cos^2 of the transmitted angle, 1 - (1 - cosI^2) / eta^2, in a form that keeps cosI^2 at grazing
    // incidence: in single precision 1 - cosI^2 rounds to 1 below cosI = 2.4e-4, which made an
    // index-matched surface reflect totally.
    const real cos2T = (eta * eta - 1.0 + cosI * cosI) / (eta * eta);
    transmitted = real3(0.0);
    if (cos2T <= 0.0) return false;
    const real cosT = sqrt(cos2T);
    transmitted = -toViewer / eta + (cosI / eta - cosT) * normal;
    return true;
}

// Whether light seen at cosine cosI from the normal, eta relative across the interface, is reflected totally
// (no transmitted direction: refractThrough fails, fresnelDielectric is 1).
VKRT_FN bool totallyReflects(real cosI, real eta) {
    cosI = clamp(cosI, 0.0, 1.0);
    return (eta * eta - 1.0 + cosI * cosI) / (eta * eta) <= 0.0;
}

// Unpolarised Fresnel reflectance of a dielectric interface (Born and Wolf): the mean of the s and p
// reflectances. cosI is the cosine on the incident side, eta = n_transmitted / n_incident; 1 for total
// internal reflection.
VKRT_FN real fresnelDielectric(real cosI, real eta) {
    cosI = clamp(cosI, 0.0, 1.0);
    const real cos2T = (eta * eta - 1.0 + cosI * cosI) / (eta * eta);  // as in refractThrough
    if (cos2T <= 0.0) return 1.0;  // total internal reflection (totallyReflects)
    const real cosT = sqrt(cos2T);
    const real rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const real rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// Schlick's approximation, used for metals whose F0 is their base colour.
VKRT_FN real3 fresnelSchlick(real3 f0, real cosI) {
    const real m = pow(1.0 - clamp(cosI, 0.0, 1.0), 5.0);
    return f0 + (real3(1.0) - f0) * m;
}

// Reflectance at normal incidence of a dielectric with index `ior` in air.
VKRT_FN real dielectricF0(real ior) {
    const real r = (ior - 1.0) / (ior + 1.0);
    return r * r;
}

// `v` turned by the smallest rotation that takes unit vector `from` to unit vector `to` (Rodrigues). Nearly
// equal or opposite vectors (within the precision's tolerance) leave `v`, or give `to`.
VKRT_FN real3 rotateLike(real3 v, real3 from, real3 to, real tolerance) {
    const real3 axis = cross(from, to);
    const real sine = length(axis), cosine = dot(from, to);
    if (!(sine > tolerance) || cosine <= -1.0 + tolerance) return cosine < 0.0 ? to : v;
    const real3 k = axis / sine;
    return v * cosine + cross(k, v) * sine + k * dot(k, v) * (1.0 - cosine);
}

// `v` turned as a moving triangle turned between two of its poses: by the rotation that takes the frame of its
// first edge and its unit normal in the first pose to that frame in the second (exact for a rigid motion; a
// deforming triangle's first edge stands for its turn). The smallest rotation of the normal alone (rotateLike)
// leaves out the triangle's turn about its normal, which shows in the tangents of normal textures. Frames that
// are equal leave `v` as it is; a degenerate edge falls back on rotateLike.
VKRT_FN real3 turnWithFace(real3 v, real3 edgeFrom, real3 normalFrom, real3 edgeTo, real3 normalTo, real tolerance) {
    const real3 alongFrom = edgeFrom - normalFrom * dot(edgeFrom, normalFrom);
    const real3 alongTo = edgeTo - normalTo * dot(edgeTo, normalTo);
    const real lengthFrom = length(alongFrom), lengthTo = length(alongTo);
    if (!(lengthFrom > 0.0) || !(lengthTo > 0.0)) return rotateLike(v, normalFrom, normalTo, tolerance);
    const real3 tangentFrom = alongFrom / lengthFrom, tangentTo = alongTo / lengthTo;
    if (tangentFrom == tangentTo && normalFrom == normalTo) return v;
    return tangentTo * dot(v, tangentFrom) + cross(normalTo, tangentTo) * dot(v, cross(normalFrom, tangentFrom)) +
           normalTo * dot(v, normalFrom);
}

// The unit normal of a triangle's plane (right-handed winding), its cross product evaluated as written: no
// product is fused into a multiply-add, so a component whose two products are equal (0 on an axis-aligned face)
// is exactly 0 on every device, as on the CPU; a fused one would leave it at plus or minus a rounding error,
// which orthonormalBasis's branch could see. `normalize` squares the components, which in single precision
// overflows beyond a cross product of about 1.8e19 (a triangle's edges near 4e9) and flushes to zero below about
// 1e-19 (edges near 3e-10): such a cross product is divided by its largest component first.
VKRT_FN real3 planeNormal(real3 v0, real3 v1, real3 v2) {
    const real3 a = v1 - v0, b = v2 - v0;
    VKRT_PRECISE const real3 normal = real3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    const real lengthSquared = dot(normal, normal);
    if (lengthSquared > 1e-30 && lengthSquared < 1e30) return normalize(normal);
    return normalize(normal / max(abs(normal.x), max(abs(normal.y), abs(normal.z))));
}

// An orthonormal basis with `n` as its third axis (Duff et al., "Building an Orthonormal Basis, Revisited",
// JCGT 6(1), 2017). Its two branches give different bases, and a sample drawn in one of them goes elsewhere
// than in the other, so they part where normals seldom are: at z = 1 - sqrt(2), 114.5 degrees from +z, not at
// zero. Faces in the plane z = 0 (a Y-up scene's walls) are common, and their normals' z is 0, -0 or a
// rounding error of either sign, which differs between devices: a skewed wall's face normal, -1.1e-7, against
// its file's vertex normal, +0, sent the paths bouncing off it in mirrored directions; and Vulkan does not make
// a shader keep the sign of zero (on an H200 the Cornell box's paths went other ways than the CPU's until -0
// took the branch of +0).
VKRT_FN void orthonormalBasis(real3 n, VKRT_OUT(real3) b1, VKRT_OUT(real3) b2) {
    // The first branch is regular for any z above -1 (a = -1 / (1 + z)), the second for any below 1.
    const real sign = n.z >= -0.41421356 ? 1.0 : -1.0;
    const real a = -1.0 / (sign + n.z);
    const real b = n.x * n.y * a;
    b1 = real3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = real3(b, sign + n.y * n.y * a, -n.y);
}

// The power heuristic (Veach 1997) for `count` samples of density `pdf` against one of density `other`.
VKRT_FN real powerHeuristic(real count, real pdf, real other) {
    const real a = count * pdf;
    const real sum = a * a + other * other;
    return sum > 0.0 ? a * a / sum : 0.0;
}

VKRT_FN real luminance(real3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

VKRT_SHADING_END

#endif  // VKRT_OPTICS_H
