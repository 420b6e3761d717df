// Emissive triangles and spheres as area lights. The device picks one in proportion to its power (the table
// lives with the scene, host/scene/light_table.h); these functions then choose a point on it and give the
// densities that multiple importance sampling weighs. A triangle is sampled uniformly by area; a sphere by
// solid angle, uniformly inside the cone it subtends from the shading point (uniformly by area when the point
// is inside it).
#ifndef VKRT_AREA_LIGHT_H
#define VKRT_AREA_LIGHT_H

#include "optics.h"
#include "shading_language.h"
#include "shape_geometry.h"
#include "sphere_geometry.h"

VKRT_SHADING_BEGIN

// A point on an emissive primitive.
struct LightPoint {
    uint primitive;
    uint material;  // the emitting surface's
    real3 position;
    real3 normal;  // the emitting (front, outward) side
    real2 uv;      // barycentric weights of v1 and v2 (triangles) or texture coordinates (spheres)
    real pdfArea;  // per unit area, the choice of the light included
};

// A light's power, by which light sampling picks it: luminance times area (at the shutter's opening).
VKRT_FN real lightPower(real3 emission, real area) { return area * max(luminance(emission), 1e-12); }

VKRT_FN real triangleArea(real3 v0, real3 v1, real3 v2) { return 0.5 * length(cross(v1 - v0, v2 - v0)); }

// A uniform point on a triangle (Shirley and Chiu's square-root mapping); `pdfArea` is the light's pick
// probability over its area.
VKRT_FN LightPoint sampleTriangleLight(uint primitive, real3 v0, real3 v1, real3 v2, real pdfArea, real u, real v) {
    LightPoint p;
    p.primitive = primitive;
    p.material = 0u;  // the device's to fill in
    const real root = sqrt(u);
    p.uv = real2(root * (1.0 - v), root * v);
    p.position = (1.0 - root) * v0 + p.uv.x * v1 + p.uv.y * v2;
    p.normal = planeNormal(v0, v1, v2);
    p.pdfArea = pdfArea;
    return p;
}

// Whether sphere lights are sampled by area from `from` at squared distance `distance2` from the centre: from
// inside, and from points within a ten-thousandth of the radius of the surface, where the cone of a point
// outside closes up. Uniform area sampling is right from any point, so the shell only trades variance for
// robustness: a shading point on the sphere itself (an emitter seen from inside) rounds to either side of it,
// and the cone's sampler then drew every point next to the shading point (light leaked inside a one-sided
// sphere, a double-sided one came out 10% dark). sphereLightSolidAnglePdf decides alike.
VKRT_FN bool sphereSampledByArea(real radius, real distance2) {
    return distance2 <= radius * radius * (1.0 + 2e-4);
}

// A point of a sphere picked with probability `pick`, uniform in the cone of directions it subtends from
// `from` (pbrt-v4, Sphere::Sample), or uniform by area from inside or on its surface (sphereSampledByArea).
VKRT_FN LightPoint sampleSphereLight(uint primitive, real3 center, real radius, real pick, real3 from, real u,
                                     real v) {
    LightPoint p;
    p.primitive = primitive;
    p.material = 0u;  // the device's to fill in
    const real3 toCenter = center - from;
    const real distance2 = dot(toCenter, toCenter);
    const real phi = 2.0 * VKRT_PI * v;
    real oneMinusCosMax = 0.0;
    if (sphereSampledByArea(radius, distance2)) {
        const real z = 1.0 - 2.0 * u, ring = sqrt(max(0.0, 1.0 - z * z));
        p.normal = real3(ring * cos(phi), ring * sin(phi), z);
        p.pdfArea = pick / (4.0 * VKRT_PI * radius * radius);
    } else {
        const real3 axis = toCenter / sqrt(distance2);
        const real sin2Max = radius * radius / distance2;
        const real sinMax = sqrt(sin2Max);
        oneMinusCosMax = coneOneMinusCos(radius, distance2);
        const real oneMinusCos = u * oneMinusCosMax;
        const real cosTheta = 1.0 - oneMinusCos;
        const real sin2Theta = oneMinusCos * (2.0 - oneMinusCos);
        // The angle at the centre between the axis (reversed) and the sampled point.
        const real cosAlpha = sin2Theta / sinMax + cosTheta * sqrt(max(0.0, 1.0 - sin2Theta / sin2Max));
        const real sinAlpha = sqrt(max(0.0, 1.0 - cosAlpha * cosAlpha));
        real3 b1, b2;
        orthonormalBasis(axis, b1, b2);
        p.normal = -(sinAlpha * cos(phi) * b1 + sinAlpha * sin(phi) * b2 + cosAlpha * axis);
        p.pdfArea = 0.0;
    }
    p.position = center + radius * p.normal;
    p.uv = sphereUv(p.normal);
    if (oneMinusCosMax > 0.0) {
        // The cone's solid-angle density 1 / (2 pi (1 - cos theta_max)), per unit area at the point.
        const real3 offset = p.position - from;
        const real d2 = dot(offset, offset);
        const real cosLight = max(0.0, -dot(p.normal, offset) / sqrt(d2));
        p.pdfArea = pick * cosLight / (2.0 * VKRT_PI * oneMinusCosMax * d2);
    }
    return p;
}

// The density per unit solid angle, seen from a point at squared distance `distance2`, of a light point
// sampled with density `pdfArea` per unit area whose normal makes cosine `cosLight` with the direction back.
VKRT_FN real solidAnglePdfFromArea(real pdfArea, real distance2, real cosLight) {
    return cosLight > 0.0 ? pdfArea * distance2 / cosLight : 0.0;
}

// The density per unit solid angle with which sampleSphereLight, seen from `from`, picks a point at squared
// distance `distance2` and cosine `cosLight` on a sphere picked with probability `pick`.
VKRT_FN real sphereLightSolidAnglePdf(real3 center, real radius, real pick, real3 from, real distance2,
                                      real cosLight) {
    if (!(cosLight > 0.0)) return 0.0;
    const real3 toCenter = center - from;
    const real centerDistance2 = dot(toCenter, toCenter);
    if (!sphereSampledByArea(radius, centerDistance2))
        return pick / (2.0 * VKRT_PI * coneOneMinusCos(radius, centerDistance2));
    return pick / (4.0 * VKRT_PI * radius * radius) * distance2 / cosLight;
}

// Shapes (VKRT_shape) as lights. A shape is sampled part by part (the sphere; a box face; the cylinder's side
// and caps; the cone's side and base), each part chosen by its weight (its area in the world, exact for flat
// parts, estimated from four normals for curved ones), and uniformly by area over the canonical part. The
// density per world area then follows from Nanson's formula, dA_world = |det M| |M^-T n| dA_object for
// object-to-world map M: exact under any affine map, whatever the part weights.

// |det M| |M^-T n| for world-to-object map `toObject` (M^-1) and object-space unit normal n.
VKRT_FN real shapeAreaScale(VKRT_IN(AffineRows) toObject, real3 n) {
    const real determinant = dot(real3(toObject.row0), cross(real3(toObject.row1), real3(toObject.row2)));
    return length(affineTransposedVector(toObject, n)) / abs(determinant);
}

VKRT_FN uint shapePartCount(uint type) {
    return type == VKRT_SHAPE_SPHERE     ? 1u
           : type == VKRT_SHAPE_BOX      ? 6u
           : type == VKRT_SHAPE_CYLINDER ? 3u
                                         : 2u;
}

// The area of canonical part `part` (numbered as the faces, shape_geometry.h).
VKRT_FN real shapePartArea(uint type, uint part) {
    if (type == VKRT_SHAPE_SPHERE) return 4.0 * VKRT_PI;
    if (type == VKRT_SHAPE_BOX) return 4.0;
    if (part != VKRT_FACE_SIDE) return VKRT_PI;
    return type == VKRT_SHAPE_CYLINDER ? 4.0 * VKRT_PI
                                       : VKRT_PI * sqrt(5.0);  // the cone's slant height is sqrt 5
}

// A part's weight: its canonical area times the area scale of its normal (flat parts), or the mean scale of
// four (curved parts: the sphere's and the round sides' normals along +-x and +-z, the sphere's also +-y).
VKRT_FN real shapePartWeight(uint type, uint part, VKRT_IN(AffineRows) toObject) {
    const real area = shapePartArea(type, part);
    if (type == VKRT_SHAPE_BOX || part != VKRT_FACE_SIDE)
        return area * shapeAreaScale(toObject, shapeNormal(type, part, real3(0.0)));
    const real lean = type == VKRT_SHAPE_CONE ? 0.5 : 0.0;
    real sum = shapeAreaScale(toObject, normalize(real3(1.0, lean, 0.0))) +
               shapeAreaScale(toObject, normalize(real3(-1.0, lean, 0.0))) +
               shapeAreaScale(toObject, normalize(real3(0.0, lean, 1.0))) +
               shapeAreaScale(toObject, normalize(real3(0.0, lean, -1.0)));
    if (type == VKRT_SHAPE_SPHERE) {
        sum +=
            shapeAreaScale(toObject, real3(0.0, 1.0, 0.0)) + shapeAreaScale(toObject, real3(0.0, -1.0, 0.0));
        return area * sum / 6.0;
    }
    return area * sum / 4.0;
}

// The shape's estimated area in the world: its parts' weights (exact for boxes).
VKRT_FN real shapeArea(uint type, VKRT_IN(AffineRows) toObject) {
    real sum = 0.0;
    for (uint part = 0u; part < shapePartCount(type); ++part) sum += shapePartWeight(type, part, toObject);
    return sum;
}

// The density per world area with which sampleShapePoint picks object-space point p of face `face`.
VKRT_FN real shapePointDensity(uint type, uint face, real3 p, VKRT_IN(AffineRows) toObject) {
    const real partProbability = shapePartWeight(type, face, toObject) / shapeArea(type, toObject);
    return partProbability /
           (shapePartArea(type, face) * shapeAreaScale(toObject, shapeNormal(type, face, p)));
}

// A point of a shape's surface in object space (u, v in [0, 1)), and its face.
VKRT_FN real3 sampleShapePoint(uint type, VKRT_IN(AffineRows) toObject, real u, real v, VKRT_OUT(uint) face) {
    // The part by weight, then u rescaled to [0, 1) within it.
    const real total = shapeArea(type, toObject);
    const uint parts = shapePartCount(type);
    face = parts - 1u;
    real below = 0.0;
    for (uint part = 0u; part + 1u < parts; ++part) {
        const real weight = shapePartWeight(type, part, toObject) / total;
        if (u < below + weight) {
            face = part;
            break;
        }
        below += weight;
    }
    const real weight = shapePartWeight(type, face, toObject) / total;
    u = clamp((u - below) / weight, 0.0, 0.99999994);
    const real phi = 2.0 * VKRT_PI * v;
    if (type == VKRT_SHAPE_SPHERE) {
        const real z = 1.0 - 2.0 * u, ring = sqrt(max(0.0, 1.0 - z * z));
        return real3(ring * cos(phi), ring * sin(phi), z);
    }
    if (type == VKRT_SHAPE_BOX) {
        const int axis = int(face / 2u);
        real3 p = real3(0.0);
        p[axis] = (face & 1u) != 0u ? 1.0 : -1.0;
        p[(axis + 1) % 3] = 2.0 * u - 1.0;
        p[(axis + 2) % 3] = 2.0 * v - 1.0;
        return p;
    }
    if (face != VKRT_FACE_SIDE) {
        const real r = sqrt(u);
        return real3(r * sin(phi), face == VKRT_FACE_TOP ? 1.0 : -1.0, r * cos(phi));
    }
    if (type == VKRT_SHAPE_CYLINDER) return real3(sin(phi), 2.0 * u - 1.0, cos(phi));
    // The cone's side: its area grows with w = 1 - y, so w = 2 sqrt(u).
    const real w = 2.0 * sqrt(u);
    return real3(0.5 * w * sin(phi), 1.0 - w, 0.5 * w * cos(phi));
}

VKRT_SHADING_END

#endif  // VKRT_AREA_LIGHT_H
