#include "scene/light_table.h"

#include <algorithm>
#include <cmath>

#include "area_light.h"

namespace vkrt {

double primitiveArea(const Scene& scene, uint32_t primitive) {
    if (scene.isSphere(primitive)) {
        const double r = scene.sphereOf(primitive).radius;
        return 4.0 * M_PI * r * r;
    }
    const Triangle& t = scene.triangles[primitive];
    return shading::triangleArea(glm::dvec3(t.v0), glm::dvec3(t.v1), glm::dvec3(t.v2));
}

LightTable buildLightTable(const Scene& scene) {
    LightTable table;
    std::vector<double> power, area;
    auto add = [&](uint32_t primitive) {
        const double a = primitiveArea(scene, primitive);
        const double p =
            shading::lightPower(glm::dvec3(scene.materials[scene.materialOf(primitive)].emission), a);
        if (!(a > 0.0) || !std::isfinite(p)) return;
        table.primitives.push_back(primitive);
        power.push_back(p);
        area.push_back(a);
    };
    for (uint32_t index : scene.emissiveTriangles) add(index);
    for (uint32_t index : scene.emissiveSpheres) add(static_cast<uint32_t>(scene.triangles.size()) + index);
    for (double p : power) table.totalPower += p;
    double running = 0.0;
    for (size_t i = 0; i < power.size(); ++i) {
        running += power[i];
        table.cdf.push_back(running / table.totalPower);
        table.pick.push_back(power[i] / table.totalPower);
        table.pdfArea.push_back(power[i] / table.totalPower / area[i]);
    }
    if (!table.cdf.empty()) table.cdf.back() = 1.0;
    return table;
}

size_t LightTable::find(double u) const {
    const size_t i = std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin();
    return std::min(i, cdf.size() - 1);
}

}  // namespace vkrt
