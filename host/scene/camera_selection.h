// Choosing the camera to render from: one of the file's camera instances, or a generated camera that
// frames the whole scene when the file has none.
#pragma once

#include "scene/scene.h"

namespace vkrt {

// A perspective camera looking at the centre of `bounds` along -Z, far enough back that the bounding
// sphere fits the vertical field of view.
Camera frameBounds(const Aabb& bounds, double aspectRatio);

// A perspective camera at `eye` looking at `target`, its film upright (+Y up), with vertical field of view
// `yfov` in radians; `target - eye` must not be vertical.
Camera lookAtCamera(const glm::dvec3& eye, const glm::dvec3& target, double yfov);

// The camera with index `index` (in node order); throws SceneError when it does not exist. With no
// cameras in the file, index 0 gives the framing camera.
Camera selectCamera(const Scene& scene, int index, double aspectRatio);

}  // namespace vkrt
