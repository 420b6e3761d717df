// Rays against solids (VKRT_shape, VKRT_csg) in double precision: each shape's interval along the ray, and
// the crossings of the solid's surface that shaders/shape_geometry.h finds from them. The reference
// renderer's side; the GPU's is shaders/traverse.glsl.
#pragma once

#include <cstdint>

#include "optics.h"
#include "scene/scene.h"
#include "shape_geometry.h"

namespace vkrt {

// The intervals along one ray of a solid's shapes, at one shutter time.
struct SolidIntervals {
    double tIn[VKRT_CSG_MAX_SHAPES];
    double tOut[VKRT_CSG_MAX_SHAPES];
    uint32_t faceIn[VKRT_CSG_MAX_SHAPES];
    uint32_t faceOut[VKRT_CSG_MAX_SHAPES];
    uint32_t count = 0;
    glm::uvec4 tableLow{0u}, tableHigh{0u};
    double originScale = 0.0;  // the ray origin's largest coordinate (csgCrossing's ties grow with it)
};

inline SolidIntervals solidIntervals(const Scene& scene, const Solid& solid, const glm::dvec3& origin,
                                     const glm::dvec3& direction, double time) {
    SolidIntervals s;
    s.count = solid.shapeCount;
    s.tableLow = solid.tableLow();
    s.tableHigh = solid.tableHigh();
    s.originScale = shading::maxAbs(origin);
    for (uint32_t i = 0; i < solid.shapeCount; ++i) {
        glm::dmat4 toWorld, toObject;
        scene.shapeAt(solid.firstShape + i, time, toWorld, toObject);
        const glm::dvec3 o(toObject * glm::dvec4(origin, 1.0)), d(toObject * glm::dvec4(direction, 0.0));
        if (!shading::shapeInterval(scene.shapes[solid.firstShape + i].type, o, d, s.tIn[i], s.tOut[i],
                                    s.faceIn[i], s.faceOut[i])) {
            s.tIn[i] = shading::kInfinity;
            s.tOut[i] = -shading::kInfinity;
        }
    }
    return s;
}

inline bool solidCrossing(SolidIntervals& s, double tAfter, double tLimit, shading::CsgCrossing& crossing) {
    return shading::csgCrossing(s.tIn, s.tOut, s.faceIn, s.faceOut, s.count, s.tableLow, s.tableHigh, tAfter,
                                tLimit, s.originScale, crossing);
}

// A crossing as a hit's two numbers (SurfaceHit::u and v): the scene's shape, and face * 2 + flip.
inline void encodeCrossing(const Solid& solid, const shading::CsgCrossing& crossing, double& u, double& v) {
    u = static_cast<double>(solid.firstShape + crossing.shape);
    v = static_cast<double>(crossing.face * 2u + (crossing.flip ? 1u : 0u));
}

}  // namespace vkrt
