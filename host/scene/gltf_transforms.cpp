#include "scene/gltf_transforms.h"

#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/gltf_animation.h"
#include "scene/gltf_context.h"

namespace vkrt {

glm::dmat4 trsMatrix(const glm::dvec3& translation, const glm::dquat& rotation, const glm::dvec3& scale) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translation);
    m = m * glm::mat4_cast(rotation);
    return glm::scale(m, scale);
}

glm::dmat4 localTransform(const GltfContext& context, int nodeIndex) {
    const tinygltf::Node& node = context.model.nodes[nodeIndex];
    const std::string where = describe("node", nodeIndex, node.name);
    auto check = [&](const std::vector<double>& v, size_t n, const char* what) {
        if (!v.empty() && v.size() != n)
            context.fail(where + ": " + what + " must have " + std::to_string(n) + " numbers");
        if (!allFinite(v)) context.fail(where + ": " + what + " is not finite");
    };
    check(node.matrix, 16, "matrix");
    check(node.translation, 3, "translation");
    check(node.rotation, 4, "rotation");
    check(node.scale, 3, "scale");
    if (!node.matrix.empty()) {
        glm::dmat4 m;
        for (int column = 0; column < 4; ++column) {
            for (int row = 0; row < 4; ++row) m[column][row] = node.matrix[column * 4 + row];  // column-major
        }
        return m;
    }
    // Absent values take glTF's defaults: no translation, the identity rotation, unit scale.
    glm::dvec3 translation(0.0), scale(1.0);
    glm::dquat rotation(1.0, 0.0, 0.0, 0.0);
    if (!node.translation.empty())
        translation = {node.translation[0], node.translation[1], node.translation[2]};
    if (!node.rotation.empty()) {
        // glTF stores quaternions as (x, y, z, w); GLM's constructor takes (w, x, y, z).
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        double len = glm::length(q);
        if (!(len > 0.0)) context.fail(where + ": rotation quaternion has zero length");
        rotation = q / len;
    }
    if (!node.scale.empty()) scale = {node.scale[0], node.scale[1], node.scale[2]};
    return trsMatrix(translation, rotation, scale);
}

glm::dmat4 localTransformAt(const GltfContext& context, const NodeAnimations& animations, int nodeIndex,
                            double time) {
    if (!animations.animates(nodeIndex)) return localTransform(context, nodeIndex);
    const tinygltf::Node& node = context.model.nodes[nodeIndex];
    localTransform(context, nodeIndex);  // validates the static values
    // The rest pose, whose animated parts the channels replace.
    NodeTrs rest;
    if (!node.translation.empty())
        rest.translation = {node.translation[0], node.translation[1], node.translation[2]};
    if (!node.rotation.empty()) {
        rest.rotation = glm::normalize(
            glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    }
    if (!node.scale.empty()) rest.scale = {node.scale[0], node.scale[1], node.scale[2]};
    return animations.evaluate(nodeIndex, rest, time).matrix();
}

}  // namespace vkrt
