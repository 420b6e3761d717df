#include "scene/light_table.h"

#include <algorithm>
#include <cmath>

#include "area_light.h"
#include "punctual_light.h"
#include "scene/sampling_grid.h"
#include "shared.h"

namespace vkrt {

double primitiveArea(const Scene& scene, uint32_t primitive) {
    if (scene.isSphere(primitive)) {
        const double r = scene.sphereOf(primitive).radius;
        return 4.0 * M_PI * r * r;
    }
    const Triangle& t = scene.triangles[primitive];
    return shading::triangleArea(glm::dvec3(t.v0), glm::dvec3(t.v1), glm::dvec3(t.v2));
}

double shapeArea(const Scene& scene, uint32_t shape) {
    const Shape& s = scene.shapes[shape];
    return shading::shapeArea(s.type, shading::affineRows(s.toObject));
}

std::vector<uint32_t> solidOfShapes(const Scene& scene) {
    std::vector<uint32_t> solid(scene.shapes.size());
    for (uint32_t i = 0; i < scene.solids.size(); ++i) {
        for (uint32_t k = 0; k < scene.solids[i].shapeCount; ++k)
            solid[scene.solids[i].firstShape + k] = scene.firstSolid() + i;
    }
    return solid;
}

namespace {

// Each light's pick probability (lightPickProbability) of `power`, as cumulative steps on the 2^-48 grid, and
// as the probability those steps state.
void pickTable(const std::vector<double>& power, std::vector<uint64_t>& steps, std::vector<double>& pick,
               double& totalPower) {
    totalPower = 0.0;
    for (double p : power) totalPower += p;
    const uint32_t count = static_cast<uint32_t>(power.size());
    std::vector<double> probability(count);
    for (uint32_t i = 0; i < count; ++i) {
        probability[i] = totalPower > 0.0 ? shading::lightPickProbability(power[i], totalPower, count)
                                          : 1.0 / count;  // lights of no power: uniformly
    }
    steps = gridCdf(probability, LightTable::kLightSteps);
    for (uint32_t i = 0; i < count; ++i) {
        const uint64_t own = steps[i] - (i > 0 ? steps[i - 1] : 0);
        pick.push_back(static_cast<double>(own) / static_cast<double>(LightTable::kLightSteps));
    }
}

// The first entry whose cumulative steps exceed `u`.
size_t findStep(const std::vector<uint64_t>& steps, uint64_t u) {
    const size_t i = std::upper_bound(steps.begin(), steps.end(), u) - steps.begin();
    return std::min(i, steps.size() - 1);
}

}  // namespace

LightTable buildLightTable(const Scene& scene) {
    LightTable table;
    std::vector<double> power, area;
    auto add = [&](uint32_t primitive, uint32_t shape, double a, uint32_t material) {
        const double p = shading::lightPower(glm::dvec3(scene.materials[material].emission), a);
        if (!(a > 0.0) || !std::isfinite(p)) return;
        table.primitives.push_back(primitive);
        table.shapes.push_back(shape);
        power.push_back(p);
        area.push_back(a);
    };
    for (uint32_t index : scene.emissiveTriangles)
        add(index, VKRT_NO_PRIMITIVE, primitiveArea(scene, index), scene.triangles[index].material);
    for (uint32_t index : scene.emissiveSpheres) {
        const uint32_t primitive = static_cast<uint32_t>(scene.triangles.size()) + index;
        add(primitive, VKRT_NO_PRIMITIVE, primitiveArea(scene, primitive), scene.spheres[index].material);
    }
    const std::vector<uint32_t> solids = solidOfShapes(scene);
    for (uint32_t shape : scene.emissiveShapes)
        add(solids[shape], shape, shapeArea(scene, shape), scene.shapes[shape].material);
    pickTable(power, table.steps, table.pick, table.totalPower);
    for (size_t i = 0; i < area.size(); ++i) table.pdfArea.push_back(table.pick[i] / area[i]);
    table.solidAngleTriangles = samplesTrianglesBySolidAngle(scene);
    return table;
}

bool samplesTrianglesBySolidAngle(const Scene& scene) {
    // A lamp is large beside the scene where one of its triangles covers a fiftieth of the square of the
    // scene's diagonal (a sky or ceiling quad over the scene, a panel beside it): sampling by solid angle
    // then takes the distance and the light's cosine out of the estimate, and its variance falls by orders of
    // magnitude. For lamps like the Cornell box's (0.0075) the error stayed the same, while the sampler's
    // code alone, never run, made lavapipe's kernel 17% slower (registers), so there it is left out.
    const glm::dvec3 diagonal = glm::dvec3(scene.bounds.max) - glm::dvec3(scene.bounds.min);
    for (uint32_t index : scene.emissiveTriangles) {
        if (primitiveArea(scene, index) >= 0.02 * glm::dot(diagonal, diagonal)) return true;
    }
    return false;
}

size_t LightTable::find(uint64_t u) const {
    return findStep(steps, u);
}

PunctualLightTable buildPunctualLightTable(const Scene& scene) {
    PunctualLightTable table;
    if (scene.lights.size() <= VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO) return table;
    const double radius =
        scene.bounds.empty() ? 1.0
                             : 0.5 * glm::length(glm::dvec3(scene.bounds.max) - glm::dvec3(scene.bounds.min));
    std::vector<double> power;
    for (const PunctualLight& light : scene.lights) {
        const double intensity =
            shading::luminance(glm::dvec3(light.color) * static_cast<double>(light.intensity));
        double spread = 4.0 * M_PI;  // the solid angle a point light shines into
        if (light.type == LightType::Spot)
            spread = 2.0 * M_PI * (1.0 - std::cos(static_cast<double>(light.outerConeAngle)));
        if (light.type == LightType::Directional) spread = M_PI * radius * radius;
        const double p = intensity * spread;
        power.push_back(std::isfinite(p) && p > 0.0 ? p : 0.0);
    }
    double total = 0.0;
    pickTable(power, table.steps, table.pick, total);
    return table;
}

size_t PunctualLightTable::find(uint64_t u) const {
    return findStep(steps, u);
}

}  // namespace vkrt
