// The table by which both renderers pick an emissive primitive (triangle or sphere) as a light: in
// proportion to its power, luminance times area at the shutter's opening (shaders/area_light.h lightPower).
// A point on the chosen light is then sampled by shaders/area_light.h.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

struct LightTable {
    std::vector<uint32_t> primitives;  // the emissive primitives
    std::vector<double> cdf;           // cumulative power up to and including each, ending at 1
    std::vector<double> pick;          // each one's probability of being picked
    std::vector<double> pdfArea;       // pick probability over area: the density of a triangle's points
    double totalPower = 0.0;

    bool empty() const { return primitives.empty(); }
    // The entry that `u` in [0, 1) picks: the first whose cumulative power exceeds it.
    size_t find(double u) const;
};

LightTable buildLightTable(const Scene& scene);

// The area of triangle `index` (of Scene::triangles) or of a sphere's surface, at the shutter's opening.
double primitiveArea(const Scene& scene, uint32_t primitive);

}  // namespace vkrt
