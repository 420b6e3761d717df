// Emissive triangles and spheres as area lights. The device picks one, nine tenths in proportion to its power
// and a tenth uniformly (lightPickProbability; the table lives with the scene, host/scene/light_table.h); these
// functions then choose a point on it and give the densities that multiple importance sampling weighs. A
// triangle is sampled uniformly in the solid angle it subtends from the shading point (uniformly by area where
// that angle is tiny or near a hemisphere); a sphere uniformly inside the cone it subtends (uniformly by area
// when the point is inside it).
#ifndef VKRT_AREA_LIGHT_H
#define VKRT_AREA_LIGHT_H

#include "optics.h"
#include "random.h"
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
    // A sphere's point seen through the sphere's near side (sampleSphereLight, seeThrough): the texture
    // coordinates where the shadow ray crosses that side, whose holes it passes (the ray skips the sphere).
    bool behindNearSide;
    real2 nearSideUv;
};

// A light's power, by which light sampling picks it: luminance times area (at the shutter's opening).
VKRT_FN real lightPower(real3 emission, real area) { return area * max(luminance(emission), 1e-12); }

// The probability that light sampling picks a light of power `power` among `count` of total power `totalPower`:
// nine tenths by power, and a tenth uniformly (defensive importance sampling; Hesterberg 1995). By power alone, a
// lamp of 1e-6 of the total (a room's, beside a sun) got one sample in a million, and Whitted, which reaches it
// only by light samples, left the room black. The table (host/scene/light_table.h) holds these probabilities on
// its grid; multiple importance sampling weighs a lamp that a bounce ray meets by this function.
#define VKRT_UNIFORM_LIGHT_SHARE 0.1
VKRT_FN real lightPickProbability(real power, real totalPower, uint count) {
    return (1.0 - VKRT_UNIFORM_LIGHT_SHARE) * (power / totalPower) + VKRT_UNIFORM_LIGHT_SHARE / real(count);
}

// The 48-bit number, as its high and low 24 bits, with which a light sample reads the table: two random numbers,
// each a whole number of steps of 2^-24 (random.h), the first the high half.
VKRT_FN uvec2 lightPickSteps(real pick, real pickFine) {
    return uvec2(uint(pick * real(VKRT_RANDOM_STEPS)), uint(pickFine * real(VKRT_RANDOM_STEPS)));
}

// Half the cross product's length; where its square nears float's denormals, taken over its largest component:
// the squared length is a denormal for a triangle 1e-10 across (area 1e-21), and the GPU's pick of a light, its
// power over the total, lost its digits (the Cornell box scaled by 1e-10 came out up to 0.16% bright); at 1e-12
// the area was 0.
VKRT_FN real triangleArea(real3 v0, real3 v1, real3 v2) {
    const real3 n = cross(v1 - v0, v2 - v0);
    const real squared = dot(n, n);
    if (squared > 1e-30) return 0.5 * sqrt(squared);
    const real largest = maxComponent(abs(n));
    return largest > 0.0 ? 0.5 * largest * length(n / largest) : 0.0;
}

#ifdef VKRT_HAS_SOLID_ANGLE_TRIANGLES
// Solid-angle sampling of triangles, compiled into the shaders of scenes with a large lamp only
// (host/scene/light_table.h samplesTrianglesBySolidAngle); the CPU reference compiles it always.

// cos t and sin t for t in [0, 2 pi], to a few ulps of the type on every device: Vulkan lets a device's sin
// and cos be 2^-11 off (lavapipe's are 5e-5 off), which would swamp the small angles of a small triangle's
// sampling. The angle is brought within pi / 4 of a multiple of pi / 2 and Taylor's series taken there (the
// first omitted terms are at most 2e-14).
VKRT_FN real2 cosSin(real t) {
    const real quarter = floor(t / (0.5 * VKRT_PI) + 0.5);
    const real r = t - quarter * (0.5 * VKRT_PI);
    const real r2 = r * r;
    const real sinR =
        r * (1.0 + r2 * (-1.0 / 6.0 +
                         r2 * (1.0 / 120.0 +
                               r2 * (-1.0 / 5040.0 +
                                     r2 * (1.0 / 362880.0 + r2 * (-1.0 / 39916800.0 + r2 * (1.0 / 6227020800.0)))))));
    const real cosR =
        1.0 + r2 * (-0.5 + r2 * (1.0 / 24.0 +
                                 r2 * (-1.0 / 720.0 +
                                       r2 * (1.0 / 40320.0 +
                                             r2 * (-1.0 / 3628800.0 +
                                                   r2 * (1.0 / 479001600.0 + r2 * (-1.0 / 87178291200.0)))))));
    const uint q = uint(quarter) % 4u;
    if (q == 0u) return real2(cosR, sinR);
    if (q == 1u) return real2(-sinR, cosR);
    if (q == 2u) return real2(-cosR, -sinR);
    return real2(sinR, -cosR);
}

// atan(y, x) for y >= 0, to a few ulps of the type on every device: Vulkan lets a device's atan be 4096 ulps
// off (lavapipe's was 2e-5 relative off for a small triangle's solid angle). The ratio of the smaller to the
// larger of |x| and y is halved twice (atan z = 2 atan(z / (1 + sqrt(1 + z^2)))) to at most tan(pi / 16), where
// the series to z^21 leaves less than 1e-16.
VKRT_FN real angleOf(real y, real x) {
    const real ax = abs(x);
    if (!(max(ax, y) > 0.0)) return 0.0;
    const bool steep = y > ax;
    real z = steep ? ax / y : y / ax;
    z = z / (1.0 + sqrt(1.0 + z * z));
    z = z / (1.0 + sqrt(1.0 + z * z));
    const real z2 = z * z;
    real series = 1.0 / 21.0;
    series = 1.0 / 19.0 - z2 * series;
    series = 1.0 / 17.0 - z2 * series;
    series = 1.0 / 15.0 - z2 * series;
    series = 1.0 / 13.0 - z2 * series;
    series = 1.0 / 11.0 - z2 * series;
    series = 1.0 / 9.0 - z2 * series;
    series = 1.0 / 7.0 - z2 * series;
    series = 1.0 / 5.0 - z2 * series;
    series = 1.0 / 3.0 - z2 * series;
    series = 1.0 - z2 * series;
    real angle = 4.0 * z * series;
    if (steep) angle = 0.5 * VKRT_PI - angle;
    return x < 0.0 ? VKRT_PI - angle : angle;
}

// A triangle seen from a point as a spherical triangle: the unit directions to its corners, the angle at the
// first one (its cosine and sine), the side from a to b (its sine and 1 - its cosine), the direction along
// the side from a towards c, and the solid angle it covers (area; 0 where it is degenerate seen from there:
// the point in the triangle's plane or on an edge).
struct SphericalTriangle {
    real3 a, b, c;
    real cosAlpha, sinAlpha;
    real sinAB, versinAB;
    real3 towardsC;
    real area;
};

// Everything is taken from the corners' offsets and the triangle's edges rather than from differences of the
// unit directions, which lose their digits when the triangle looks small, and in ratios of lengths, which float
// holds at any scale (products of lengths are denormals in a scene scaled by 1e-10). The solid angle is Van
// Oosterom and Strackee's (1983), 2 atan(|a . (b x c)|, 1 + a.b + b.c + c.a): Girard's sum of the angles less
// pi, from arcsines, came out 3e-4 off at 0.33 sr on lavapipe.
VKRT_FN SphericalTriangle sphericalTriangle(real3 v0, real3 v1, real3 v2, real3 from) {
    SphericalTriangle s;
    const real3 d0 = v0 - from, d1 = v1 - from, d2 = v2 - from;
    const real l0 = length(d0), l1 = length(d1), l2 = length(d2);
    s.a = d0 / l0;
    s.b = d1 / l1;
    s.c = d2 / l2;
    s.cosAlpha = 1.0;
    s.sinAlpha = 0.0;
    s.sinAB = 0.0;
    s.versinAB = 0.0;
    s.towardsC = real3(0.0);
    s.area = 0.0;
    const real3 e1 = v1 - v0, e2 = v2 - v0;
    const real m1 = length(e1), m2 = length(e2);
    if (!(l0 > 0.0 && l1 > 0.0 && l2 > 0.0 && m1 > 0.0 && m2 > 0.0)) return s;
    const real3 u1 = e1 / m1, u2 = e2 / m2;
    // The normals of the planes through `from` and the edges at v0 (to v1, to v2): the angle between them is the
    // one at a, and their cross product is a times the triple product a . (u1 x u2).
    const real3 nb = cross(s.a, u1), nc = cross(s.a, u2);
    const real lb = length(nb), lc = length(nc);
    const real tripleProduct = abs(dot(s.a, cross(u1, u2)));
    if (!(lb > 0.0 && lc > 0.0 && tripleProduct > 0.0)) return s;
    s.cosAlpha = dot(nb / lb, nc / lc);
    s.sinAlpha = tripleProduct / lb / lc;
    s.sinAB = lb * (m1 / l1);
    const real3 chord = s.b - s.a;
    s.versinAB = 0.5 * dot(chord, chord);
    s.towardsC = normalize(u2 - dot(u2, s.a) * s.a);
    s.area = 2.0 * angleOf(tripleProduct * (m1 / l1) * (m2 / l2),
                           1.0 + dot(s.a, s.b) + dot(s.b, s.c) + dot(s.c, s.a));
    return s;
}

// Whether a triangle of solid angle `area` is sampled by solid angle: Arvo's mapping loses its digits for tiny
// spherical triangles (their angles sum to pi less a rounding error) and fails near a hemisphere, where uniform
// area sampling is used instead (pbrt-v4's bounds). Both are right from any point; solid angle takes the
// distance and the light's cosine out of the estimate, which area sampling leaves in (a surface next to a large
// lamp saw fireflies).
VKRT_FN bool triangleSampledBySolidAngle(real area) { return area >= 3e-4 && area <= 6.22; }

// Whether a triangle is large as seen from `from`: its area over the squared distance to its centroid above
// 0.1, about its solid angle where that is small. Smaller ones are sampled by area: for them the two strategies
// differ little, and area sampling costs a fraction.
VKRT_FN bool triangleLooksLarge(real3 v0, real3 v1, real3 v2, real3 from) {
    const real3 toCentroid = (v0 + v1 + v2) / 3.0 - from;
    return triangleArea(v0, v1, v2) > 0.1 * dot(toCentroid, toCentroid);
}

// In a scene with a large lamp (host/scene/light_table.h), the spherical triangle a triangle is sampled in from
// `from`; its area 0 where the triangle is sampled by area: where it looks small, and where Arvo's mapping would
// fail.
VKRT_FN SphericalTriangle sampledSphericalTriangle(real3 v0, real3 v1, real3 v2, real3 from) {
    SphericalTriangle s;
    s.area = 0.0;
    if (triangleLooksLarge(v0, v1, v2, from)) s = sphericalTriangle(v0, v1, v2, from);
    if (!triangleSampledBySolidAngle(s.area)) s.area = 0.0;
    return s;
}

// The point of sampleTriangleLight where it samples spherical triangle `s` (of corners v0, v1, v2 seen from
// `from`) uniformly: its position, barycentrics and density per unit area.
VKRT_FN void pointInSolidAngle(VKRT_IN(SphericalTriangle) s, real3 v0, real3 v1, real3 v2, real3 from, real pick,
                               real u, real v, VKRT_INOUT(LightPoint) p) {
    // The part of area u * A next to corner a is cut off by the arc from b to a point c' on the side from a to c
    // (Arvo's mapping). With h = u A / 2 and P = sin^2 h + sin^2(alpha - h), c' lies at an angle from a whose
    // cosine and sine are proportional to (1 - cos(ab)) P - 2 sin^2 h and 2 sin h sin(alpha - h) sin(ab): Arvo's
    // cosine rewritten in half angles, so that the sine needs no 1 - cos^2 (taken so, c' strayed up to 1.3e-3 off
    // the side at u = 0 in single precision).
    const real2 halfAngle = cosSin(0.5 * u * s.area);
    const real sinRest = s.sinAlpha * halfAngle.x - s.cosAlpha * halfAngle.y;  // sin(alpha - h), positive
    const real sin2H = halfAngle.y * halfAngle.y, sin2Rest = sinRest * sinRest;
    const real P = sin2H + sin2Rest;
    const real3 cp = normalize((s.versinAB * P - 2.0 * sin2H) * s.a +
                               (2.0 * abs(halfAngle.y * sinRest) * s.sinAB) * s.towardsC);
    // Then uniformly along the arc from b to c' by the cosine to b; 1 - cos is half the squared chord, which
    // keeps its digits for short arcs.
    const real3 chord = cp - s.b;
    const real oneMinusCos = v * 0.5 * dot(chord, chord);
    const real cosTheta = 1.0 - oneMinusCos;
    const real sinTheta = sqrt(max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
    const real3 across = chord - dot(chord, s.b) * s.b;
    const real acrossLength = length(across);
    const real3 w = acrossLength > 0.0 ? cosTheta * s.b + (sinTheta / acrossLength) * across : s.b;
    // Where that direction meets the triangle, as barycentrics (Moller-Trumbore from `from`).
    const real3 e1 = v1 - v0, e2 = v2 - v0;
    const real3 s1 = cross(w, e2);
    const real divisor = dot(s1, e1);
    const real3 offset = from - v0;
    real b1 = divisor != 0.0 ? clamp(dot(offset, s1) / divisor, 0.0, 1.0) : 1.0 / 3.0;
    real b2 = divisor != 0.0 ? clamp(dot(w, cross(offset, e1)) / divisor, 0.0, 1.0) : 1.0 / 3.0;
    if (b1 + b2 > 1.0) {
        const real sum = b1 + b2;
        b1 /= sum;
        b2 /= sum;
    }
    p.uv = real2(b1, b2);
    p.position = (1.0 - b1 - b2) * v0 + b1 * v1 + b2 * v2;
    // The solid-angle density pick / A, per unit area at the point: times |cos| / d^2 (no d^3, which is a
    // denormal, its digits gone, for a point 1e-13 from the light).
    const real3 toPoint = p.position - from;
    const real d2 = dot(toPoint, toPoint);
    p.pdfArea = d2 > 0.0 ? pick * abs(dot(p.normal, toPoint / sqrt(d2))) / (d2 * s.area) : 0.0;
}
#endif  // VKRT_HAS_SOLID_ANGLE_TRIANGLES

// A point of a triangle picked with probability `pick` (`pdfArea`: pick over its area), seen from `from`:
// uniform in the solid angle it subtends (Arvo, "Stratified Sampling of Spherical Triangles", SIGGRAPH 1995, as
// pbrt-v4's SampleSphericalTriangle writes it) where sampledSphericalTriangle says so, else uniform by area
// (Shirley and Chiu's square-root mapping). `pdfArea` of the result is per unit area at the point, the pick
// included.
VKRT_FN LightPoint sampleTriangleLight(uint primitive, real3 v0, real3 v1, real3 v2, real pick, real pdfArea,
                                       real3 from, bool bySolidAngle, real u, real v) {
    LightPoint p;
    p.primitive = primitive;
    p.material = 0u;  // the device's to fill in
    p.behindNearSide = false;
    p.nearSideUv = real2(0.0);
    p.normal = planeNormal(v0, v1, v2);
#ifdef VKRT_HAS_SOLID_ANGLE_TRIANGLES
    if (bySolidAngle) {
        const SphericalTriangle s = sampledSphericalTriangle(v0, v1, v2, from);
        if (s.area > 0.0) {
            pointInSolidAngle(s, v0, v1, v2, from, pick, u, v, p);
            return p;
        }
    }
#endif
    const real root = sqrt(u);
    p.uv = real2(root * (1.0 - v), root * v);
    p.position = (1.0 - root) * v0 + p.uv.x * v1 + p.uv.y * v2;
    p.pdfArea = pdfArea;
    return p;
}

// The density per solid angle with which sampleTriangleLight, seen from `from` (and told `bySolidAngle`), picks a
// point at squared distance `distance2` and cosine `cosLight` on a triangle picked with probability `pick`
// (`pdfArea` per unit area).
VKRT_FN real triangleLightSolidAnglePdf(real3 v0, real3 v1, real3 v2, real pick, real pdfArea, real3 from,
                                        bool bySolidAngle, real distance2, real cosLight) {
    if (!(cosLight > 0.0)) return 0.0;
#ifdef VKRT_HAS_SOLID_ANGLE_TRIANGLES
    if (bySolidAngle) {
        const real area = sampledSphericalTriangle(v0, v1, v2, from).area;
        if (area > 0.0) return pick / area;
    }
#endif
    return pdfArea * distance2 / cosLight;
}

// Whether sphere lights are sampled by area from `from` at squared distance `distance2` from the centre: from
// inside, and from points within a ten-thousandth of the radius of the surface, where the cone of a point
// outside closes up. Uniform area sampling is right from any point, so the shell only trades variance for
// robustness: a shading point on the sphere itself (an emitter seen from inside) rounds to either side of it,
// and the cone's sampler then drew every point next to the shading point (light leaked inside a one-sided
// sphere, a double-sided one came out 10% dark). sphereLightSolidAnglePdf decides alike.
// A sphere that can be seen through (`seeThrough`: double-sided, with holes) is sampled by area from everywhere:
// the inside of its far half, seen through the holes of the near half, lights points outside too, and the cone
// holds the near half alone (a translucent double-sided lamp lit a floor as 0.5 of its opaque self where 0.75 is
// right).
VKRT_FN bool sphereSampledByArea(real radius, real distance2, bool seeThrough) {
    return seeThrough || distance2 <= radius * radius * (1.0 + 2e-4);
}

// A point of a sphere picked with probability `pick`, uniform in the cone of directions it subtends from
// `from` (pbrt-v4, Sphere::Sample), or uniform by area from inside or on its surface, or where it can be seen
// through (sphereSampledByArea).
VKRT_FN LightPoint sampleSphereLight(uint primitive, real3 center, real radius, real pick, real3 from,
                                     bool seeThrough, real u, real v) {
    LightPoint p;
    p.primitive = primitive;
    p.material = 0u;  // the device's to fill in
    p.behindNearSide = false;
    p.nearSideUv = real2(0.0);
    const real3 toCenter = center - from;
    const real distance2 = dot(toCenter, toCenter);
    const real phi = 2.0 * VKRT_PI * v;
    real oneMinusCosMax = 0.0;
    if (sphereSampledByArea(radius, distance2, seeThrough)) {
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
    const real3 offset = p.position - from;
    if (seeThrough && !sphereSampledByArea(radius, distance2, false) && dot(p.normal, offset) > 0.0) {
        // From outside (beyond the shell where a point on the sphere itself may round to), a point facing away
        // lies behind the near side: the line from `from` crosses it first, at t_near = 2 (c - o).d - t_far
        // along the unit direction d (the roots' sum), at near d - (c - o) from the centre.
        const real far = length(offset);
        const real3 d = offset / far;
        const real near = 2.0 * dot(toCenter, d) - far;
        p.behindNearSide = true;
        p.nearSideUv = sphereUv(normalize(near * d - toCenter));
    }
    if (oneMinusCosMax > 0.0) {
        // The cone's solid-angle density 1 / (2 pi (1 - cos theta_max)), per unit area at the point.
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
VKRT_FN real sphereLightSolidAnglePdf(real3 center, real radius, real pick, real3 from, bool seeThrough,
                                      real distance2, real cosLight) {
    if (!(cosLight > 0.0)) return 0.0;
    const real3 toCenter = center - from;
    const real centerDistance2 = dot(toCenter, toCenter);
    if (!sphereSampledByArea(radius, centerDistance2, seeThrough))
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
