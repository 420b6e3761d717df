// The GPU's side of solids (VKRT_shape, VKRT_csg): their shapes' maps at the sample's shutter time and their
// intervals along a ray, for traverse.glsl, the hit points and light sampling. The geometry itself is shared
// with the CPU reference (shape_geometry.h), and so is sampling shapes as lights (shape_light.h). Requires
// `params` and scene_arrays.glsl in scope.
#ifndef VKRT_SOLIDS_GLSL
#define VKRT_SOLIDS_GLSL

#include "shape_geometry.h"

#ifdef VKRT_HAS_SHAPES
bool isSolid(GpuPrimitive primitive) {
    return (primitive.kind & VKRT_PRIMITIVE_KIND_MASK) == VKRT_PRIMITIVE_SOLID;
}

GpuSolid solidOf(GpuPrimitive primitive) {
    return gpuSolidAt(primitive.kind >> VKRT_PRIMITIVE_INDEX_SHIFT);
}

// How many shapes `solid` has: 1, a constant, in a kernel for a scene of single shapes (shape_geometry.h's
// VKRT_SOLID_SHAPES).
uint shapeCountOf(GpuSolid solid) {
#if VKRT_SOLID_SHAPES == 1
    return 1u;
#else
    return solid.shapeCount;
#endif
}

// Shape `shape`'s type (shape_geometry.h's VKRT_SHAPE_*). Where every shape of the scene has one type
// (VKRT_HAS_SHAPE_<TYPE> alone), that constant: the shared geometry's branches on the type then fold, and the
// other types' code is left out of the kernel.
#if defined(VKRT_HAS_SHAPE_SPHERES) && !defined(VKRT_HAS_SHAPE_BOXES) && !defined(VKRT_HAS_SHAPE_CYLINDERS) && \
    !defined(VKRT_HAS_SHAPE_CONES)
#define VKRT_SHAPE_TYPE VKRT_SHAPE_SPHERE
#elif defined(VKRT_HAS_SHAPE_BOXES) && !defined(VKRT_HAS_SHAPE_SPHERES) && !defined(VKRT_HAS_SHAPE_CYLINDERS) && \
    !defined(VKRT_HAS_SHAPE_CONES)
#define VKRT_SHAPE_TYPE VKRT_SHAPE_BOX
#elif defined(VKRT_HAS_SHAPE_CYLINDERS) && !defined(VKRT_HAS_SHAPE_SPHERES) && !defined(VKRT_HAS_SHAPE_BOXES) && \
    !defined(VKRT_HAS_SHAPE_CONES)
#define VKRT_SHAPE_TYPE VKRT_SHAPE_CYLINDER
#elif defined(VKRT_HAS_SHAPE_CONES) && !defined(VKRT_HAS_SHAPE_SPHERES) && !defined(VKRT_HAS_SHAPE_BOXES) && \
    !defined(VKRT_HAS_SHAPE_CYLINDERS)
#define VKRT_SHAPE_TYPE VKRT_SHAPE_CONE
#endif
uint shapeTypeAt(uint shape) {
#ifdef VKRT_SHAPE_TYPE
    return VKRT_SHAPE_TYPE;
#else
    return gpuShapeAt(shape).type;
#endif
}

// Shape `shape`'s world-to-object and object-to-world maps at the sample's shutter time: with motion, its
// object-to-world map interpolated between poses (as triangles' corners are) and inverted.
void shapeMaps(uint shape, out AffineRows toObject, out AffineRows toWorld) {
    const GpuShape s = gpuShapeAt(shape);
    toObject = AffineRows(s.toObject0, s.toObject1, s.toObject2);
    toWorld = AffineRows(s.toWorld0, s.toWorld1, s.toWorld2);
#ifdef VKRT_HAS_MOTION
    const uint segments = params.motionSegments;
    const float x = vkrtShutterTime * float(segments);
    const uint segment = min(uint(x), segments - 1u);
    const float f = x - float(segment);
    if (segment > 0u) {
        const GpuShapePose a = gpuShapePoseAt(shape * segments + segment - 1u);
        toWorld = AffineRows(a.row0, a.row1, a.row2);
    }
    const GpuShapePose b = gpuShapePoseAt(shape * segments + segment);
    toWorld.row0 += f * (b.row0 - toWorld.row0);
    toWorld.row1 += f * (b.row1 - toWorld.row1);
    toWorld.row2 += f * (b.row2 - toWorld.row2);
    // GLSL's matrices are built column by column: the rows' transpose.
    const mat3 linear = transpose(mat3(toWorld.row0.xyz, toWorld.row1.xyz, toWorld.row2.xyz));
    const mat3 inverted = inverse(linear);
    const vec3 translation = -(inverted * vec3(toWorld.row0.w, toWorld.row1.w, toWorld.row2.w));
    const mat3 rows = transpose(inverted);
    toObject = AffineRows(vec4(rows[0], translation.x), vec4(rows[1], translation.y), vec4(rows[2], translation.z));
#endif
}

// The intervals of the line origin + t direction with each of a solid's shapes (misses as (+inf, -inf)); entries
// beyond the solid's shapes are left unset. (Each pass of a loop counts against llvmpipe's budget per invocation,
// traverse.glsl, so the loop runs over the solid's shapes only.)
void solidIntervals(GpuSolid solid, vec3 origin, vec3 direction, out float tIn[VKRT_SOLID_SHAPES],
                    out float tOut[VKRT_SOLID_SHAPES], out uint faceIn[VKRT_SOLID_SHAPES],
                    out uint faceOut[VKRT_SOLID_SHAPES]) {
    for (uint i = 0u; i < VKRT_SOLID_SHAPES; ++i) {  // unrolled (shape_geometry.h)
        if (i >= shapeCountOf(solid)) continue;
        AffineRows toObject, toWorld;
        shapeMaps(solid.firstShape + i, toObject, toWorld);
        float a, b;
        uint fa, fb;
        const bool hit = shapeInterval(shapeTypeAt(solid.firstShape + i), affinePoint(toObject, origin),
                                       affineVector(toObject, direction), a, b, fa, fb);
        tIn[i] = hit ? a : VKRT_INFINITY;
        tOut[i] = hit ? b : -VKRT_INFINITY;
        faceIn[i] = fa;
        faceOut[i] = fb;
    }
}
#endif

#endif
