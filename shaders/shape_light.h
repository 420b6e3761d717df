// Emissive shapes of solids (VKRT_shape, VKRT_csg) as area lights, shared by both devices: a point of the
// shape drawn uniformly over its canonical parts, its density per world area by Nanson's formula
// (area_light.h's shapePointDensity), and whether it lies on its solid's surface at all (a CSG operand emits
// only there), and the density per solid angle with which it picks a point. Each device gives its shapes
// through VKRT_DEVICE (shading_language.h): shapeType, shapeMaterial, and shapeMaps (object-to-world and
// world-to-object at the sample's shutter time).
#ifndef VKRT_SHAPE_LIGHT_H
#define VKRT_SHAPE_LIGHT_H

#include "area_light.h"
#include "shading_language.h"
#include "shape_geometry.h"

#ifdef VKRT_HAS_SHAPES
VKRT_SHADING_BEGIN

// A solid as its lights see it: its shapes (the scene's firstShape to firstShape + shapeCount - 1) and its
// truth table over their inside bits (shape_geometry.h's csgTable).
struct SolidOperands {
    uint firstShape;
    uint shapeCount;
    uvec4 tableLow;
    uvec4 tableHigh;
};

// Whether world point `p`, on shape `shape` of `solid` (outward unit normal `normal`), lies on the solid's
// surface and emits there: 0 if not, 1 where the solid's outside is the shape's, -1 where it is the shape's
// inside (a subtracted shape). The other shapes are asked just inside and just outside the face, `reach`
// along the normal (a tie's width, csgCrossing's): the solid's inside bit on the two sides differs exactly on
// its surface. Another shape's face coincident with this one (an L of two flush boxes) is crossed with it, as
// csgCrossing crosses it, and the surface there emits from one shape alone, the one csgCrossing puts the
// crossing of a ray arriving from outside on (the light it sends): the first whose own toggle makes the
// solid's inside, else the first crossed. Asked at the point itself, a union of two flush boxes lost those
// faces' light, and an intersection emitted it twice.
VKRT_DEVICE_TEMPLATE
VKRT_FN int solidSide(VKRT_DEVICE_PARAM VKRT_IN(SolidOperands) solid, uint shape, real3 p, real3 normal,
                      real reach) {
    const real3 step = reach * normal;
    uint before = 0u, after = 0u;  // the other shapes holding the points just inside and just outside
    for (uint k = 0u; k < solid.shapeCount; ++k) {
        const uint other = solid.firstShape + k;
        if (other == shape) continue;
        AffineRows toObject, toWorld;
        VKRT_DEVICE(shapeMaps)(other, toObject, toWorld);
        const uint type = VKRT_DEVICE(shapeType)(other);
        if (shapeContains(type, affinePoint(toObject, p - step))) before |= 1u << k;
        if (shapeContains(type, affinePoint(toObject, p + step))) after |= 1u << k;
    }
    const uint own = 1u << (shape - solid.firstShape);
    const bool insideBefore = csgTable(solid.tableLow, solid.tableHigh, before | own);
    const bool insideAfter = csgTable(solid.tableLow, solid.tableHigh, after);
    if (insideBefore == insideAfter) return 0;
    const uint crossed = (before ^ after) | own;
    const uint outside = insideBefore ? after : (before | own);  // the shapes holding the side a ray comes from
    uint chosen = solid.shapeCount, first = solid.shapeCount;
    for (uint k = 0u; k < solid.shapeCount; ++k) {
        if (((crossed >> k) & 1u) == 0u) continue;
        if (first == solid.shapeCount) first = k;
        if (chosen == solid.shapeCount && csgTable(solid.tableLow, solid.tableHigh, outside ^ (1u << k))) chosen = k;
    }
    if (chosen == solid.shapeCount) chosen = first;
    if (solid.firstShape + chosen != shape) return 0;
    return insideBefore ? 1 : -1;
}

// A point of shape `shape` of `solid` (scene primitive `primitive`), the light picked with probability
// `pick`, from (u, v) in [0, 1)^2. Where the point is not on the solid's surface it carries nothing (pdfArea
// 0); where the solid's outside is the shape's inside, the emitting side is the shape's inside.
VKRT_DEVICE_TEMPLATE
VKRT_FN LightPoint sampleShapeLight(VKRT_DEVICE_PARAM uint primitive, VKRT_IN(SolidOperands) solid,
                                    uint shape, real pick, real u, real v) {
    const uint type = VKRT_DEVICE(shapeType)(shape);
    AffineRows toObject, toWorld;
    VKRT_DEVICE(shapeMaps)(shape, toObject, toWorld);
    uint face;
    const real3 local = sampleShapePoint(type, toObject, u, v, face);
    LightPoint p;
    p.primitive = primitive;
    p.material = VKRT_DEVICE(shapeMaterial)(shape);
    p.behindNearSide = false;  // a solid's own faces shadow it (its shadow rays do not skip it)
    p.nearSideUv = real2(0.0);
    p.position = affinePoint(toWorld, local);
    const real3 outward = normalize(affineTransposedVector(toObject, shapeNormal(type, face, local)));
    const real reach = VKRT_CSG_TIE * shapeSize(toWorld) + VKRT_CSG_PLACEMENT_TIE * shapeOffset(toWorld);
    const int side = solidSide(VKRT_DEVICE_ARG solid, shape, p.position, outward, reach);
    p.normal = (side < 0 ? -1.0 : 1.0) * outward;
    p.uv = shapeUv(type, face, local);
    p.pdfArea = side == 0 ? 0.0 : pick * shapePointDensity(type, face, local, toObject);
    return p;
}

// The density per solid angle, seen from `from`, with which sampleShapeLight picks `point` on shape `shape`,
// whose light is picked with probability `pick`; `cosLight` is the cosine at the light.
VKRT_DEVICE_TEMPLATE
VKRT_FN real shapeLightSolidAnglePdf(VKRT_DEVICE_PARAM uint shape, real pick, real3 from, real3 point,
                                     real cosLight) {
    const uint type = VKRT_DEVICE(shapeType)(shape);
    AffineRows toObject, toWorld;
    VKRT_DEVICE(shapeMaps)(shape, toObject, toWorld);
    const real3 local = affinePoint(toObject, point);
    const real3 toPoint = point - from;
    return solidAnglePdfFromArea(pick * shapePointDensity(type, shapeFaceAt(type, local), local, toObject),
                                 dot(toPoint, toPoint), cosLight);
}

VKRT_SHADING_END
#endif  // VKRT_HAS_SHAPES

#endif  // VKRT_SHAPE_LIGHT_H
