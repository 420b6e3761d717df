// The table by which both renderers pick an emissive primitive (triangle, sphere or a solid's shape) as a
// light: nine tenths in proportion to its power, luminance times area at the shutter's opening, and a tenth
// uniformly (shaders/area_light.h lightPickProbability). A point on the chosen light is then sampled by
// shaders/area_light.h.
//
// The table is on a grid of 2^-48 (scene/sampling_grid.h), read with two of the 24-bit random numbers as one
// 48-bit number: each light is picked with exactly the probability the table states, on both devices alike,
// and a light of a millionth of the power among many is not picked with a probability off by a step of 2^-24
// (6% of its own at 1e-6).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

struct LightTable {
    std::vector<uint32_t> primitives;  // the emissive primitives
    std::vector<uint32_t> shapes;      // for a solid's shape, the scene's shape; else VKRT_NO_PRIMITIVE
    std::vector<uint64_t> steps;       // the cumulative steps up to and including each, ending at kLightSteps
    std::vector<double> pick;          // each one's probability of being picked: its steps over kLightSteps
    std::vector<double> pdfArea;       // pick probability over area: the density of a triangle's points
    double totalPower = 0.0;
    // Whether triangles that look large from the shading point are sampled by the solid angle they cover
    // (shaders/area_light.h sampledSphericalTriangle): where some emissive triangle is large beside the
    // scene.
    bool solidAngleTriangles = false;

    static constexpr uint64_t kLightSteps = uint64_t(1) << 48;

    bool empty() const { return primitives.empty(); }
    // The entry that the 48-bit number `u` in [0, kLightSteps) picks: the first whose cumulative steps exceed
    // it.
    size_t find(uint64_t u) const;
};

LightTable buildLightTable(const Scene& scene);

// The table by which both renderers pick a punctual light where a scene has more than
// VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO (shaders/punctual_light.h), on the same grid and with the same shares as
// LightTable's: nine tenths by power (the luminance of its intensity times the solid angle it shines into, 4
// pi for a point light and 2 pi (1 - cos(outer angle)) for a spot; a directional light's irradiance times the
// scene's cross-section, pi r^2 for the sphere around its bounds) and a tenth uniformly. Empty for fewer
// lights.
struct PunctualLightTable {
    // The cumulative steps up to and including each light, ending at kLightSteps, and the probability of
    // each.
    std::vector<uint64_t> steps;
    std::vector<double> pick;

    bool empty() const { return steps.empty(); }
    size_t find(uint64_t u) const;  // as LightTable::find
};

PunctualLightTable buildPunctualLightTable(const Scene& scene);

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
