#include "scene/procedural_meshes.h"

#include <cmath>

#include "random.h"

namespace vkrt {

std::vector<Triangle> makeUvSphere(glm::vec3 center, float radius, int rings, int segments,
                                   uint32_t material) {
    auto point = [&](int ring, int segment) {
        const double theta = M_PI * ring / rings;
        const double phi = 2.0 * M_PI * segment / segments;
        return center + radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                           std::sin(theta) * std::sin(phi));
    };
    std::vector<Triangle> triangles;
    triangles.reserve(static_cast<size_t>(2) * rings * segments);
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            const glm::vec3 a = point(r, s), b = point(r, s + 1), c = point(r + 1, s),
                            d = point(r + 1, s + 1);
            triangles.push_back({a, b, c, material});
            triangles.push_back({b, d, c, material});
        }
    }
    return triangles;
}

std::vector<Triangle> makeTriangleSoup(size_t count, uint32_t seed, float size, uint32_t material) {
    std::vector<Triangle> triangles(count);
    uint32_t dimension = 0;
    auto next = [&] { return vkrtRandom(seed, 0, 0, dimension++); };
    for (Triangle& t : triangles) {
        const glm::vec3 base(next(), next(), next());
        t.v0 = base;
        t.v1 = base + size * glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f);
        t.v2 = base + size * glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f);
        t.material = material;
    }
    return triangles;
}

}  // namespace vkrt
