// Analytic shapes and their constructive solid geometry (VKRT_shape and VKRT_csg, docs/vkrt_shape.md): the
// canonical convex shapes in object space, and the walk that finds where a ray crosses the surface of a CSG
// object. One source for the CPU reference (double) and the GPU (float).
//
// Every shape is convex, so a ray (a line) is inside it over one interval. A CSG object of up to
// VKRT_CSG_MAX_SHAPES shapes is a boolean function of its shapes' inside bits, which the host tabulates (a
// truth table of 2^count bits); walking the intervals' ends in order of distance and toggling bits, the first
// change of the table's value is where the ray crosses the object's surface. A single shape is an object with
// one shape and the table "inside".
#ifndef VKRT_SHAPE_GEOMETRY_H
#define VKRT_SHAPE_GEOMETRY_H

#include "shading_language.h"
#include "sphere_geometry.h"
#include "texture_density.h"

#define VKRT_SHAPE_SPHERE 0u    // radius 1 around the origin
#define VKRT_SHAPE_BOX 1u       // [-1, 1]^3
#define VKRT_SHAPE_CYLINDER 2u  // radius 1 around +Y, from y = -1 to 1, capped
#define VKRT_SHAPE_CONE 3u      // apex (0, 1, 0), base of radius 1 at y = -1, capped

// The most shapes in one CSG object (the truth table's 256 bits are two uvec4).
#define VKRT_CSG_MAX_SHAPES 8
// The most shapes a solid of this build holds: where some solid is a CSG object of several (VKRT_HAS_CSG), the
// most of the scene's solids have (the host's VKRT_SOLID_SHAPES) or VKRT_CSG_MAX_SHAPES (the CPU, the all-features
// shader); else 1. The loops over a solid's shapes run that many passes, each past the solid's own count doing
// nothing, so that lavapipe's compiler unrolls them and keeps the shapes' intervals in registers: on lavapipe
// a loop runs whole, masked, at every pass of a walk that any lane needs (issue 13). A kernel for a scene of
// single shapes then runs each once, and they fold away (surfaces.gltf's GPU time 0.67 to 0.74 of what it was);
// one whose solids have up to 3 shapes (csg.gltf), 0.89.
#ifndef VKRT_HAS_CSG
#undef VKRT_SOLID_SHAPES
#define VKRT_SOLID_SHAPES 1
#elif !defined(VKRT_SOLID_SHAPES)
#define VKRT_SOLID_SHAPES VKRT_CSG_MAX_SHAPES
#endif
// Interval ends within this relative distance of each other are crossed together, so faces that two operands
// share (coincident faces, touching operands) do not speckle with rounding: 2^-18, 32 float ulps.
#define VKRT_CSG_TIE 3.814697265625e-6
// And within this much of the magnitude of the coordinates they came from (the ray origin's largest): the
// shapes' maps are stored in float, so faces meant to coincide lie apart by the rounding of their placement,
// half an ulp of it; 2^-22, two ulps. A tie of 2^-18 of that magnitude merged walls 0.05 thick 1e5 from the
// scene's middle.
#define VKRT_CSG_PLACEMENT_TIE 2.384185791015625e-7

// The unit roundoff of the precision the shapes are traced in (double on the CPU, float on the GPU).
#ifdef __cplusplus
#define VKRT_SHAPE_EPSILON 1.1102230246251565e-16
#else
#define VKRT_SHAPE_EPSILON 5.9604644775390625e-08
#endif

// Faces, by which a ray enters or leaves a shape: the sphere has face 0; the box 2 axis + (1 on the positive
// side); the cylinder its side 0, bottom cap 1 and top cap 2; the cone its side 0 and base 1.
#define VKRT_FACE_SIDE 0u
#define VKRT_FACE_BOTTOM 1u
#define VKRT_FACE_TOP 2u

VKRT_SHADING_BEGIN

// An affine map as three rows: p' = (dot(row0.xyz, p) + row0.w, ...).
struct AffineRows {
    real4 row0;
    real4 row1;
    real4 row2;
};

#ifdef __cplusplus
// The rows of an affine 4x4 matrix (GLM's, column-major).
inline AffineRows affineRows(const glm::dmat4& m) {
    AffineRows rows;
    rows.row0 = real4(m[0][0], m[1][0], m[2][0], m[3][0]);
    rows.row1 = real4(m[0][1], m[1][1], m[2][1], m[3][1]);
    rows.row2 = real4(m[0][2], m[1][2], m[2][2], m[3][2]);
    return rows;
}
#endif

VKRT_FN real3 affinePoint(VKRT_IN(AffineRows) m, real3 p) {
    return real3(dot(real3(m.row0), p) + m.row0.w, dot(real3(m.row1), p) + m.row1.w,
                 dot(real3(m.row2), p) + m.row2.w);
}

VKRT_FN real3 affineVector(VKRT_IN(AffineRows) m, real3 v) {
    return real3(dot(real3(m.row0), v), dot(real3(m.row1), v), dot(real3(m.row2), v));
}

// The transposed linear part applied to v: an object-space normal to world space when m maps world to object
// (the inverse transpose of the object-to-world map).
VKRT_FN real3 affineTransposedVector(VKRT_IN(AffineRows) m, real3 v) {
    return v.x * real3(m.row0) + v.y * real3(m.row1) + v.z * real3(m.row2);
}

// Intersects [tIn, tOut] with the slab lo <= origin + t direction <= hi along one axis, whose near face is
// `faceLo` (at lo) or `faceHi`; false when the interval is now empty.
VKRT_FN bool clipSlab(real origin, real direction, real lo, real hi, uint faceLo, uint faceHi,
                      VKRT_INOUT(real) tIn, VKRT_INOUT(real) tOut, VKRT_INOUT(uint) faceIn,
                      VKRT_INOUT(uint) faceOut) {
    if (direction == 0.0) return origin >= lo && origin <= hi;
    const real tLo = (lo - origin) / direction, tHi = (hi - origin) / direction;
    const bool rising = direction > 0.0;
    const real tNear = rising ? tLo : tHi, tFar = rising ? tHi : tLo;
    if (tNear > tIn) {
        tIn = tNear;
        faceIn = rising ? faceLo : faceHi;
    }
    if (tFar < tOut) {
        tOut = tFar;
        faceOut = rising ? faceHi : faceLo;
    }
    return tIn <= tOut;
}

// The cylinder's or the cone's interval along origin + t direction (shapeInterval's, for those two).
VKRT_FN bool roundShapeInterval(uint type, real3 origin, real3 direction, VKRT_INOUT(real) tIn, VKRT_INOUT(real) tOut,
                                VKRT_INOUT(uint) faceIn, VKRT_INOUT(uint) faceOut) {
    // The cylinder's and the cone's curved side, as a quadric a t^2 + 2 halfB t + c <= 0.
    real a, halfB, c;
    if (type == VKRT_SHAPE_CYLINDER) {
        // x^2 + z^2 <= 1, with the discriminant from the axis's distance to the line (as sphereRoots).
        a = direction.x * direction.x + direction.z * direction.z;
        if (a == 0.0) {
            if (origin.x * origin.x + origin.z * origin.z > 1.0) return false;
        } else {
            halfB = origin.x * direction.x + origin.z * direction.z;
            const real lx = origin.x - (halfB / a) * direction.x, lz = origin.z - (halfB / a) * direction.z;
            const real discriminant = a * (1.0 - (lx * lx + lz * lz));
            if (!(discriminant >= 0.0)) return false;
            c = origin.x * origin.x + origin.z * origin.z - 1.0;
            const real q = -halfB + (halfB > 0.0 ? -sqrt(discriminant) : sqrt(discriminant));
            const real r0 = q != 0.0 ? c / q : 0.0, r1 = q / a;
            tIn = min(r0, r1);
            tOut = max(r0, r1);
        }
        return clipSlab(origin.y, direction.y, -1.0, 1.0, VKRT_FACE_BOTTOM, VKRT_FACE_TOP, tIn, tOut, faceIn,
                        faceOut);
    }
    // The cone: x^2 + z^2 <= (w / 2)^2 with w = 1 - y >= 0 (the nappe below the apex), and y >= -1.
    const real w0 = 1.0 - origin.y, dw = -direction.y;
    a = direction.x * direction.x + direction.z * direction.z - 0.25 * dw * dw;
    halfB = origin.x * direction.x + origin.z * direction.z - 0.25 * w0 * dw;
    c = origin.x * origin.x + origin.z * origin.z - 0.25 * w0 * w0;
    // Parallel to a ruling, within rounding (a's terms cancel; its sign is then noise, and would pick the
    // wrong one of a segment and two half-lines): one root of 2 halfB t + c = 0, the far root at infinity.
    const real scale = direction.x * direction.x + direction.z * direction.z + 0.25 * dw * dw;
    if (abs(a) <= 8.0 * VKRT_SHAPE_EPSILON * scale) {
        if (halfB == 0.0) {
            if (c > 0.0) return false;
        } else if (halfB > 0.0) {
            tOut = -c / (2.0 * halfB);
        } else {
            tIn = -c / (2.0 * halfB);
        }
    } else {
        const real discriminant = halfB * halfB - a * c;
        if (discriminant >= 0.0) {
            const real q = -halfB + (halfB > 0.0 ? -sqrt(discriminant) : sqrt(discriminant));
            const real r0 = q != 0.0 ? c / q : 0.0, r1 = q / a;
            const real lo = min(r0, r1), hi = max(r0, r1);
            if (a > 0.0) {
                // A segment within one nappe: keep it if it is the lower one.
                if (w0 + 0.5 * (lo + hi) * dw < 0.0) return false;
                tIn = lo;
                tOut = hi;
            } else if (dw > 0.0) {
                tIn = hi;  // the half-line that rises into w >= 0
            } else {
                tOut = lo;
            }
        } else if (a > 0.0) {
            return false;
        }
    }
    // w >= 0 (the apex's plane; it matters only where the line runs through the apex) and w <= 2 (the base).
    if (!clipSlab(w0, dw, 0.0, 2.0, VKRT_FACE_SIDE, VKRT_FACE_BOTTOM, tIn, tOut, faceIn, faceOut))
        return false;
    return true;
}


// The interval over which the line origin + t direction (object space) is inside canonical shape `type`, and
// the faces by which it enters and leaves; false when it misses. Intervals of each bounding surface are
// intersected, so a ray through an edge finds an interval on one side of it or none, never a gap.
VKRT_FN bool shapeInterval(uint type, real3 origin, real3 direction, VKRT_OUT(real) tIn, VKRT_OUT(real) tOut,
                           VKRT_OUT(uint) faceIn, VKRT_OUT(uint) faceOut) {
    tIn = -VKRT_INFINITY;
    tOut = VKRT_INFINITY;
    faceIn = VKRT_FACE_SIDE;
    faceOut = VKRT_FACE_SIDE;
    if (type == VKRT_SHAPE_SPHERE) return sphereRoots(real3(0.0), 1.0, origin, direction, tIn, tOut);
    if (type == VKRT_SHAPE_BOX) {
        for (int axis = 0; axis < 3; ++axis) {
            const uint face = 2u * uint(axis);
            if (!clipSlab(origin[axis], direction[axis], -1.0, 1.0, face, face + 1u, tIn, tOut, faceIn,
                          faceOut)) {
                return false;
            }
        }
        return true;
    }
    // The cylinder and the cone, with distances measured from the line's point nearest the cylinder's centre
    // or the cone's apex, then shifted back: from a distant origin the quadric's terms would cancel (and near
    // the apex the cone's are small, so a line by a ruling keeps its digits). The cylinder's shift waits
    // until the origin is more than 4 units away: nearer, the origin itself rounds less than the shift's sum.
    const real3 offset = type == VKRT_SHAPE_CONE ? origin - real3(0.0, 1.0, 0.0) : origin;
    const bool shifted = type == VKRT_SHAPE_CONE || dot(origin, origin) > 16.0;
    const real shift = shifted ? -dot(offset, direction) / dot(direction, direction) : 0.0;
    const bool found = roundShapeInterval(type, origin + shift * direction, direction, tIn, tOut, faceIn, faceOut);
    tIn += shift;
    tOut += shift;
    return found;
}

// The point of face `face` of shape `type` nearest to p, a point found on that face in object space (the
// rounding of the distance moves it off the surface).
VKRT_FN real3 shapeSnap(uint type, uint face, real3 p) {
    if (type == VKRT_SHAPE_SPHERE) return normalize(p);
    if (type == VKRT_SHAPE_BOX) {
        real3 snapped = clamp(p, real3(-1.0), real3(1.0));
        snapped[int(face / 2u)] = (face & 1u) != 0u ? 1.0 : -1.0;
        return snapped;
    }
    if (face == VKRT_FACE_BOTTOM) return real3(p.x, -1.0, p.z);
    if (face == VKRT_FACE_TOP) return real3(p.x, 1.0, p.z);
    const real y = clamp(p.y, -1.0, 1.0);
    const real radius = type == VKRT_SHAPE_CYLINDER ? 1.0 : 0.5 * (1.0 - y);
    const real rho = sqrt(p.x * p.x + p.z * p.z);
    if (!(rho > 0.0)) return real3(p.x, y, p.z);
    return real3(p.x * (radius / rho), y, p.z * (radius / rho));
}

// The outward unit normal of face `face` at p (object space).
VKRT_FN real3 shapeNormal(uint type, uint face, real3 p) {
    if (type == VKRT_SHAPE_SPHERE) return normalize(p);
    if (type == VKRT_SHAPE_BOX) {
        real3 n = real3(0.0);
        n[int(face / 2u)] = (face & 1u) != 0u ? 1.0 : -1.0;
        return n;
    }
    if (face == VKRT_FACE_BOTTOM) return real3(0.0, -1.0, 0.0);
    if (face == VKRT_FACE_TOP) return real3(0.0, 1.0, 0.0);
    const real rho = sqrt(p.x * p.x + p.z * p.z);
    const real nx = rho > 0.0 ? p.x / rho : 0.0, nz = rho > 0.0 ? p.z / rho : 0.0;
    // The cone's side leans out by its half-angle: the gradient of rho - (1 - y) / 2 is (x/rho, 1/2, z/rho).
    return type == VKRT_SHAPE_CYLINDER ? real3(nx, 0.0, nz) : normalize(real3(nx, 0.5, nz));
}

// The face of a point p on the surface (object space): the one it lies nearest to.
VKRT_FN uint shapeFaceAt(uint type, real3 p) {
    if (type == VKRT_SHAPE_SPHERE) return 0u;
    if (type == VKRT_SHAPE_BOX) {
        const real3 a = abs(p);
        const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
        return 2u * uint(axis) + (p[axis] > 0.0 ? 1u : 0u);
    }
    const real rho = sqrt(p.x * p.x + p.z * p.z);
    const real side = abs(rho - (type == VKRT_SHAPE_CYLINDER ? 1.0 : 0.5 * (1.0 - p.y)));
    if (abs(p.y + 1.0) < side) return VKRT_FACE_BOTTOM;
    if (type == VKRT_SHAPE_CYLINDER && abs(p.y - 1.0) < side) return VKRT_FACE_TOP;
    return VKRT_FACE_SIDE;
}

// Texture coordinates of face `face` at p (docs/vkrt_shape.md).
VKRT_FN real2 shapeUv(uint type, uint face, real3 p) {
    if (type == VKRT_SHAPE_SPHERE) return sphereUv(normalize(p));
    if (type == VKRT_SHAPE_BOX) {
        const int axis = int(face / 2u);
        return real2(0.5 * (p[(axis + 1) % 3] + 1.0), 0.5 * (1.0 - p[(axis + 2) % 3]));
    }
    if (face != VKRT_FACE_SIDE) return real2(0.5 * (p.x + 1.0), 0.5 * (p.z + 1.0));
    const real u = p.x == 0.0 && p.z == 0.0 ? 0.5 : 0.5 + atan(p.x, p.z) / (2.0 * VKRT_PI);
    return real2(u, 0.5 * (1.0 - p.y));
}

// The tangent frame of shapeUv on face `face` at p (object space) of a shape placed by `toWorld`, as a normal
// texture reads it (GpuTangents) under a texture transform's rows (sphere_geometry.h's texturedTangent): in xyz
// a unit vector along which u' grows, in w the sign that turns w * cross(normal, tangent) up the texture (the
// way v' falls, as tangent_frames.cpp decides it for meshes), with `normal` the world normal the hit reports.
// Mirroring maps and reversed normals change w. Zero where u' has no direction (a sphere's poles, a cone's
// apex): the normal then stays.
VKRT_FN real4 shapeTangent(uint type, uint face, real3 p, VKRT_IN(AffineRows) toWorld, real3 normal, real2 row0,
                           real2 row1) {
    // dP/du and dP/dv in object space, both to one positive factor (docs/vkrt_shape.md's mapping: round faces'
    // u is the longitude over 2 pi, v half the height down the side; flat faces' u and v half a coordinate).
    real3 dpdu, dpdv;
    if (type == VKRT_SHAPE_SPHERE) {
        sphereDerivatives(p, dpdu, dpdv);
    } else if (type == VKRT_SHAPE_BOX) {
        const int axis = int(face / 2u);
        dpdu = real3(0.0);
        dpdu[(axis + 1) % 3] = 1.0;
        dpdv = real3(0.0);
        dpdv[(axis + 2) % 3] = -1.0;
    } else if (face != VKRT_FACE_SIDE) {
        dpdu = real3(1.0, 0.0, 0.0);
        dpdv = real3(0.0, 0.0, 1.0);
    } else if (type == VKRT_SHAPE_CYLINDER) {
        dpdu = VKRT_PI * real3(p.z, 0.0, -p.x);
        dpdv = real3(0.0, -1.0, 0.0);
    } else {  // the cone's side, of radius rho = v, narrows towards the apex
        const real rho = sqrt(p.x * p.x + p.z * p.z);
        dpdu = 2.0 * VKRT_PI * rho * real3(p.z, 0.0, -p.x);
        dpdv = real3(p.x, -2.0 * rho, p.z);
    }
    return texturedTangent(normal, affineVector(toWorld, dpdu), affineVector(toWorld, dpdv), row0, row1);
}

// Whether p (object space) is inside shape `type`.
VKRT_FN bool shapeContains(uint type, real3 p) {
    if (type == VKRT_SHAPE_SPHERE) return dot(p, p) <= 1.0;
    if (type == VKRT_SHAPE_BOX) return max(abs(p.x), max(abs(p.y), abs(p.z))) <= 1.0;
    if (abs(p.y) > 1.0) return false;
    const real radius = type == VKRT_SHAPE_CYLINDER ? 1.0 : 0.5 * (1.0 - p.y);
    return p.x * p.x + p.z * p.z <= radius * radius;
}

// Where a ray crossed face `face` of a shape at distance t: the point on the face (object space), the solid's
// outward unit normal in the world (the shape's, reversed when `flip`), and the texture coordinates.
struct ShapePoint {
    real3 local;
    real3 normal;
    real2 uv;
};

VKRT_FN ShapePoint shapePoint(uint type, uint face, bool flip, VKRT_IN(AffineRows) toObject, real3 origin,
                              real3 direction, real t) {
    ShapePoint p;
    p.local = shapeSnap(type, face, affinePoint(toObject, origin) + t * affineVector(toObject, direction));
    const real3 n = normalize(affineTransposedVector(toObject, shapeNormal(type, face, p.local)));
    p.normal = flip ? -n : n;
    p.uv = shapeUv(type, face, p.local);
    return p;
}

// The largest row of the linear part of a shape's map `toWorld`: how far a canonical point (coordinates at
// most 1) reaches from the shape's origin along a world axis.
VKRT_FN real shapeSize(VKRT_IN(AffineRows) toWorld) {
    const real3 rows = real3(abs(toWorld.row0.x) + abs(toWorld.row0.y) + abs(toWorld.row0.z),
                             abs(toWorld.row1.x) + abs(toWorld.row1.y) + abs(toWorld.row1.z),
                             abs(toWorld.row2.x) + abs(toWorld.row2.y) + abs(toWorld.row2.z));
    return max(rows.x, max(rows.y, rows.z));
}

// The largest coordinate of a shape's translation.
VKRT_FN real shapeOffset(VKRT_IN(AffineRows) toWorld) {
    return max(abs(toWorld.row0.w), max(abs(toWorld.row1.w), abs(toWorld.row2.w)));
}

// The magnitude of the numbers a point of a shape placed by `toWorld` comes from: its translation plus its
// size.
VKRT_FN real shapeScale(VKRT_IN(AffineRows) toWorld) {
    return shapeOffset(toWorld) + shapeSize(toWorld);
}

// Texture coordinates per world unit at texture coordinates `uv` (shapeUv) of face `face` of a shape of `type`
// placed by a map of determinant `determinant` (docs/vkrt_shape.md): the square root of the ratio of areas in
// texture and object space, as triangleTextureDensity gives it on a triangle, over the map's mean linear scale.
// A box's faces and the flat caps span the unit square over 2 x 2 units (0.5); a cylinder's side spans u
// around 2 pi and v down 2 units (1 / (2 sqrt(pi))); the sphere's is a VKRT_sphere's of radius 1
// (sphereTextureDensity); a cone's side, of radius v at v and sqrt(5) from apex to rim, has 1 / (2 pi v) and
// 1 / sqrt(5), and so 1 / sqrt(2 pi v sqrt(5)) (as large at the apex as the sphere's at its poles).
VKRT_FN real shapeTextureDensity(uint type, uint face, real2 uv, real determinant) {
    real density = 0.5;
    if (type == VKRT_SHAPE_SPHERE) {
        density = sphereTextureDensity(1.0, uv.y);
    } else if (type != VKRT_SHAPE_BOX && face == VKRT_FACE_SIDE) {
        density = type == VKRT_SHAPE_CYLINDER ? 0.5 / sqrt(VKRT_PI)
                                              : 1.0 / sqrt(2.0 * VKRT_PI * max(uv.y, 1e-4) * sqrt(5.0));
    }
    return density / pow(abs(determinant), 1.0 / 3.0);
}

// Bit `state` of a CSG object's truth table: whether points inside exactly the shapes of `state`'s set bits
// are inside the object.
VKRT_FN bool csgTable(uvec4 tableLow, uvec4 tableHigh, uint state) {
    const uint word = state >> 5u;
    const uint bits = word < 4u ? tableLow[int(word)] : tableHigh[int(word - 4u)];
    return ((bits >> (state & 31u)) & 1u) != 0u;
}

// A crossing of a CSG object's surface: where, on which shape and face, and whether the object's outward
// normal there is the shape's inward one (a face of a subtracted shape).
struct CsgCrossing {
    real t;
    uint shape;  // of the object's shapes
    uint face;
    bool flip;
    real groupEnd;  // the last interval end crossed with it (a later search starts after it)
};

// The first crossing of a CSG object's surface after distance tAfter and before tLimit, given each shape's
// interval [tIn, tOut] along the ray (an empty one as (+inf, -inf)) and faces. The ray is inside shape i at
// tAfter when tIn <= tAfter < tOut. The ends ahead are taken in order, in groups: ends of other shapes within
// VKRT_CSG_TIE of a group's first are crossed together with it (coincident faces of different shapes, whose
// computed distances differ by rounding); when that changes the table's value, the crossing lies on the first
// shape whose own toggle would change it (else the first toggled). A shape's exit never joins its own entry's
// group, however thin the shape: the tie grows with the distance, and a sheet 1e-4 thick seen from 40 units
// away vanished when it did. The tie also grows with the magnitude of the coordinates the distances came from
// (VKRT_CSG_PLACEMENT_TIE of originScale, the ray origin's largest coordinate): faces meant to coincide 300
// units from the scene's middle are placed 1.5e-5 apart by their float maps, and a cut flush with a face
// there, seen from 3 units away, was sealed by a sliver.
VKRT_FN bool csgCrossing(real tIn[VKRT_SOLID_SHAPES], real tOut[VKRT_SOLID_SHAPES],
                         uint faceIn[VKRT_SOLID_SHAPES], uint faceOut[VKRT_SOLID_SHAPES], uint count,
                         uvec4 tableLow, uvec4 tableHigh, real tAfter, real tLimit, real originScale,
                         VKRT_OUT(CsgCrossing) crossing) {
#if VKRT_SOLID_SHAPES == 1
    count = 1u;  // a constant, which the loops below fold with
#endif
    crossing.t = 0.0;
    crossing.shape = 0u;
    crossing.face = 0u;
    crossing.flip = false;
    crossing.groupEnd = tAfter;
    uint state = 0u;
    uint enteredAhead = 0u, leftAhead = 0u;  // the shapes whose entry, or exit, lies ahead and is not crossed yet
    for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {
        if (i >= count) continue;
        if (tIn[i] <= tAfter && tAfter < tOut[i]) state |= 1u << i;
        if (tIn[i] > tAfter) enteredAhead |= 1u << i;
        if (tOut[i] > tAfter) leftAhead |= 1u << i;
    }
    const bool inside = csgTable(tableLow, tableHigh, state);
    real end = tAfter;  // the farthest end crossed so far
    for (uint pass = 0u; pass < 2u * count; ++pass) {
        // The nearest end ahead: a shape's entry comes before its exit.
        real next = VKRT_INFINITY;
        for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {
            if (i >= count) continue;
            if (((enteredAhead >> i) & 1u) != 0u) {
                next = min(next, tIn[i]);
            } else if (((leftAhead >> i) & 1u) != 0u) {
                next = min(next, tOut[i]);
            }
        }
        if (!(next < tLimit)) return false;
        const real groupEnd = next + VKRT_CSG_TIE * abs(next) + VKRT_CSG_PLACEMENT_TIE * originScale;
        uint toggled = 0u;
        for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {
            if (i >= count) continue;
            const uint bit = 1u << i;
            if ((enteredAhead & bit) != 0u) {
                if (tIn[i] <= groupEnd) {
                    toggled |= bit;
                    enteredAhead &= ~bit;
                    end = max(end, tIn[i]);
                }
            } else if ((leftAhead & bit) != 0u && tOut[i] <= groupEnd) {
                toggled |= bit;
                leftAhead &= ~bit;
                end = max(end, tOut[i]);
            }
        }
        const uint after = state ^ toggled;
        const bool insideAfter = csgTable(tableLow, tableHigh, after);
        if (insideAfter != inside) {
            uint chosen = count;
            for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {
                if (i >= count) continue;
                const bool alone = csgTable(tableLow, tableHigh, state ^ (1u << i)) == insideAfter;
                if (chosen == count && ((toggled >> i) & 1u) != 0u && alone) chosen = i;
            }
            if (chosen == count) {
                for (uint i = VKRT_SOLID_SHAPES; i > 0u; --i) {
                    if (i <= count && ((toggled >> (i - 1u)) & 1u) != 0u) chosen = i - 1u;
                }
            }
            const bool entersShape = ((after >> chosen) & 1u) != 0u;
            crossing.shape = chosen;
            for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {  // indexed by constants only
                if (i != chosen) continue;
                crossing.t = entersShape ? tIn[i] : tOut[i];
                crossing.face = entersShape ? faceIn[i] : faceOut[i];
            }
            crossing.flip = entersShape != insideAfter;
            crossing.groupEnd = end;
            return true;
        }
        state = after;
    }
    return false;
}

VKRT_SHADING_END

#endif  // VKRT_SHAPE_GEOMETRY_H
