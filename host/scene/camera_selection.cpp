#include "scene/camera_selection.h"

#include <algorithm>
#include <cmath>

#include "scene/scene_error.h"

namespace vkrt {

Camera frameBounds(const Aabb& bounds, double aspectRatio) {
    Camera camera;
    camera.name = "default (frames the scene)";
    camera.generated = true;
    camera.yfov = 45.0 * M_PI / 180.0;
    glm::dvec3 center(0.0), halfExtent(1.0);
    if (!bounds.empty()) {
        center = glm::dvec3(bounds.center());
        halfExtent = 0.5 * glm::dvec3(bounds.extent());
    }
    const double radius = std::max(glm::length(halfExtent), 1e-30);
    // The narrower of the two fields of view decides how far back the camera stands.
    const double halfFov = 0.5 * camera.yfov;
    const double narrowHalfFov = aspectRatio < 1.0 ? std::atan(std::tan(halfFov) * aspectRatio) : halfFov;
    const double distance = radius / std::sin(narrowHalfFov);
    camera.position = center + glm::dvec3(0.0, 0.0, distance);
    camera.forward = glm::dvec3(0.0, 0.0, -1.0);
    camera.up = glm::dvec3(0.0, 1.0, 0.0);
    camera.right = glm::dvec3(1.0, 0.0, 0.0);
    return camera;
}

Camera lookAtCamera(const glm::dvec3& eye, const glm::dvec3& target, double yfov) {
    Camera camera;
    camera.position = eye;
    camera.forward = glm::normalize(target - eye);
    camera.right = glm::normalize(glm::cross(camera.forward, glm::dvec3(0.0, 1.0, 0.0)));
    camera.up = glm::cross(camera.right, camera.forward);
    camera.yfov = yfov;
    return camera;
}

Camera selectCamera(const Scene& scene, int index, double aspectRatio) {
    if (scene.cameras.empty()) {
        if (index != 0) {
            throw SceneError(scene.sourcePath + ": --camera " + std::to_string(index) +
                             " requested, but the file has no cameras");
        }
        return frameBounds(scene.bounds, aspectRatio);
    }
    if (index < 0 || index >= static_cast<int>(scene.cameras.size())) {
        throw SceneError(scene.sourcePath + ": --camera " + std::to_string(index) +
                         " requested, but the file has " + std::to_string(scene.cameras.size()) +
                         " camera(s)");
    }
    if (!scene.cameras[index].unusable.empty()) throw SceneError(scene.cameras[index].unusable);
    return scene.cameras[index];
}

}  // namespace vkrt
