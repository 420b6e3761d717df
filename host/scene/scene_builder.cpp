#include "scene/scene_builder.h"

namespace vkrt {

void addFlatTriangle(Scene& scene, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, uint32_t material) {
    scene.triangles.push_back({v0, v1, v2, material});
    const glm::vec3 normal = glm::normalize(glm::cross(v1 - v0, v2 - v0));
    TriangleShading shading{};
    for (glm::vec3& n : shading.normal) n = normal;
    scene.shading.push_back(shading);
}

void addFlatQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t material) {
    addFlatTriangle(scene, a, b, c, material);
    addFlatTriangle(scene, a, c, d, material);
}

void finalizeScene(Scene& scene) {
    scene.bounds = Aabb{};
    scene.emissiveTriangles.clear();
    for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        scene.bounds.grow(t.bounds());
        if (scene.materials[t.material].emissive()) scene.emissiveTriangles.push_back(i);
    }
}

}  // namespace vkrt
