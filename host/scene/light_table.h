// The table by which both renderers pick an emissive primitive (triangle, sphere or a solid's shape) as a
// light: in proportion to its power, luminance times area at the shutter's opening (shaders/area_light.h
// lightPower).
// A point on the chosen light is then sampled by shaders/area_light.h.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

struct LightTable {
    std::vector<uint32_t> primitives;  // the emissive primitives
    std::vector<uint32_t> shapes;      // for a solid's shape, the scene's shape; else VKRT_NO_PRIMITIVE
    std::vector<double> cdf;           // cumulative power up to and including each, ending at 1
    std::vector<double> pick;          // each one's probability of being picked
    std::vector<double> pdfArea;       // pick probability over area: the density of a triangle's points
    double totalPower = 0.0;
    // Whether triangles that look large from the shading point are sampled by the solid angle they cover
    // (shaders/area_light.h sampledSphericalTriangle): where some emissive triangle is large beside the
    // scene.
    bool solidAngleTriangles = false;

    bool empty() const { return primitives.empty(); }
    // The entry that `u` in [0, 1) picks: the first whose cumulative power exceeds it.
    size_t find(double u) const;
};

LightTable buildLightTable(const Scene& scene);

// Whether some emissive triangle is large beside the scene (LightTable::solidAngleTriangles).
bool samplesTrianglesBySolidAngle(const Scene& scene);

// The area of triangle `index` (of Scene::triangles) or of a sphere's surface, at the shutter's opening.
double primitiveArea(const Scene& scene, uint32_t primitive);
// The area of shape `shape` (of Scene::shapes) at the shutter's opening, as light sampling weighs it
// (shaders/area_light.h shapeArea).
double shapeArea(const Scene& scene, uint32_t shape);
// The solid primitive that holds each of the scene's shapes.
std::vector<uint32_t> solidOfShapes(const Scene& scene);

}  // namespace vkrt
