#include "scene/gltf_cameras.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "scene/gltf_extensions.h"

namespace vkrt {
namespace {

// An axis of the node's transform made unit length, divided by its largest component first: under nested
// scales of product 1e-190 (valid glTF) its squared length underflowed to 0, normalize gave infinities and
// the camera was refused as singular. A zero axis still gives NaN (0 / 0), which the singularity check
// catches.
glm::dvec3 normalizeAxis(const glm::dvec3& axis) {
    const double largest = std::max({std::abs(axis.x), std::abs(axis.y), std::abs(axis.z)});
    return glm::normalize(axis / largest);
}

}  // namespace

void addCamera(GltfContext& context, int cameraIndex, const glm::dmat4& world, int nodeIndex,
               const std::string& nodeName) {
    if (cameraIndex >= static_cast<int>(context.model.cameras.size())) {
        context.fail("node '" + nodeName + "' refers to camera " + std::to_string(cameraIndex) +
                     ", which does not exist");
    }
    const tinygltf::Camera& source = context.model.cameras[cameraIndex];
    const std::string where = describe("camera", cameraIndex, source.name);
    Camera camera;
    camera.name = source.name.empty() ? (nodeName.empty() ? where : nodeName) : source.name;
    // The projection and its parameters.
    if (source.type == "perspective") {
        camera.projection = Projection::Perspective;
        camera.yfov = source.perspective.yfov;
        camera.aspectRatio = source.perspective.aspectRatio;
        if (!(camera.yfov > 0.0 && camera.yfov < M_PI)) context.fail(where + ": yfov must be in (0, pi)");
    } else if (source.type == "orthographic") {
        camera.projection = Projection::Orthographic;
        camera.xmag = source.orthographic.xmag;
        camera.ymag = source.orthographic.ymag;
        if (!(camera.xmag != 0.0 && camera.ymag != 0.0 && std::isfinite(camera.xmag) &&
              std::isfinite(camera.ymag))) {
            context.fail(where + ": xmag and ymag must be finite and non-zero");
        }
    } else {
        context.fail(where + " has unknown type '" + source.type + "'");
    }
    readCameraExtras(context, source.extras, where, camera);
    // glTF cameras look down the node's -Z, with its +X to the right and its +Y up (section 3.10.1); scale
    // and shear in the node are ignored (the axes made orthonormal, forward first). The right and up axes are
    // each the node's own, not a cross product: under a mirroring transform (a negative determinant) the
    // camera is mirrored with what it sees, and the image stays as it was.
    const glm::dmat3 linear(world);
    camera.position = glm::dvec3(world[3]);
    camera.forward = normalizeAxis(linear * glm::dvec3(0.0, 0.0, -1.0));
    const glm::dvec3 right = linear * glm::dvec3(1.0, 0.0, 0.0);
    camera.right = normalizeAxis(right - glm::dot(right, camera.forward) * camera.forward);
    const glm::dvec3 up = linear * glm::dvec3(0.0, 1.0, 0.0);
    camera.up = normalizeAxis(up - glm::dot(up, camera.forward) * camera.forward -
                              glm::dot(up, camera.right) * camera.right);
    // A node scaled to nothing (a collapsed group) is valid glTF: its camera is refused only if chosen.
    const double check = glm::dot(camera.forward + camera.right + camera.up, glm::dvec3(1.0));
    if (!std::isfinite(check) || glm::length(glm::cross(camera.forward, camera.right)) < 0.5) {
        // Several nodes may hold one camera and only one of them be singular: the node says which.
        camera.unusable = context.path + ": " + where + " at " + describe("node", nodeIndex, nodeName) +
                          ": its node transform is singular";
    }
    context.scene.cameras.push_back(camera);
}

}  // namespace vkrt
