#include "scene/gltf_nodes.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include <tiny_gltf.h>

#include "scene/gltf_accessors.h"
#include "scene/gltf_transforms.h"

namespace vkrt {

std::vector<int> sceneRoots(const GltfContext& context) {
    const tinygltf::Model& model = context.model;
    if (!model.scenes.empty()) {
        int index = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (index >= static_cast<int>(model.scenes.size())) {
            context.fail("default scene " + std::to_string(index) + " does not exist");
        }
        return model.scenes[index].nodes;
    }
    // No scene: render every node that is nobody's child.
    std::vector<bool> isChild(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes) {
        for (int child : node.children) {
            if (child >= 0 && child < static_cast<int>(isChild.size())) isChild[child] = true;
        }
    }
    std::vector<int> roots;
    for (size_t i = 0; i < isChild.size(); ++i) {
        if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    return roots;
}

void checkNodeGraph(const GltfContext& context, const std::vector<int>& roots) {
    const std::vector<tinygltf::Node>& nodes = context.model.nodes;
    const int nodeCount = static_cast<int>(nodes.size());
    // Record each node's parent, failing on bad indices, self-loops and second parents.
    std::vector<int> parent(nodeCount, -1);
    for (int i = 0; i < nodeCount; ++i) {
        for (int child : nodes[i].children) {
            if (child < 0 || child >= nodeCount) {
                context.fail(describe("node", i, nodes[i].name) + " has child " + std::to_string(child) +
                             ", which does not exist");
            }
            if (child == i) context.fail(describe("node", i, nodes[i].name) + " is its own child (a cycle)");
            if (parent[child] >= 0) {
                context.fail(describe("node", child, nodes[child].name) + " has two parents, nodes " +
                             std::to_string(parent[child]) + " and " + std::to_string(i));
            }
            parent[child] = i;
        }
    }
    // With one parent per node, a cycle is a chain of parents that returns to where it started.
    std::vector<int> state(nodeCount, 0);  // 0 unvisited, 1 on the current chain, 2 known to reach a root
    for (int start = 0; start < nodeCount; ++start) {
        std::vector<int> chain;
        int n = start;
        while (n >= 0 && state[n] == 0) {
            state[n] = 1;
            chain.push_back(n);
            n = parent[n];
        }
        if (n >= 0 && state[n] == 1) {
            context.fail("the node graph has a cycle through " + describe("node", n, nodes[n].name));
        }
        for (int c : chain) state[c] = 2;
    }
    for (int root : roots) {
        if (root < 0 || root >= nodeCount)
            context.fail("the scene refers to node " + std::to_string(root) + ", which does not exist");
        if (parent[root] >= 0)
            context.fail(describe("node", root, nodes[root].name) + " is a scene root and a child");
    }
}

namespace {

// A part of the scene as approximateCenter sees it: the world box of a mesh primitive's POSITION bounds, or
// of a sphere or shape.
struct Part {
    glm::dvec3 centre;
    glm::dvec3 halfSize;
    double size() const { return std::max({halfSize.x, halfSize.y, halfSize.z}); }
};

// The world half-size of a local box of half-size `half` under `world`'s linear part.
glm::dvec3 worldHalfSize(const glm::dmat4& world, const glm::dvec3& half) {
    glm::dvec3 result(0.0);
    for (int column = 0; column < 3; ++column) result += glm::abs(glm::dvec3(world[column])) * half[column];
    return result;
}

// Per axis, the median of `points` (the lower of the middle two for an even count).
glm::dvec3 medianOf(const std::vector<glm::dvec3>& points) {
    glm::dvec3 median;
    std::vector<double> values(points.size());
    for (int axis = 0; axis < 3; ++axis) {
        for (size_t i = 0; i < points.size(); ++i) values[i] = points[i][axis];
        const auto middle = values.begin() + static_cast<std::ptrdiff_t>((values.size() - 1) / 2);
        std::nth_element(values.begin(), middle, values.end());
        median[axis] = *middle;
    }
    return median;
}

}  // namespace

glm::dvec3 approximateCenter(const GltfContext& context, const std::vector<int>& roots) {
    const tinygltf::Model& model = context.model;
    // A skinned mesh is where its joints put it, not where its node is (glTF 2.0 section 3.7.3.3): its bounds
    // are placed by its skin's first joint, at rest, times that joint's inverse bind matrix.
    std::vector<int> parent(model.nodes.size(), -1);
    for (size_t n = 0; n < model.nodes.size(); ++n)
        for (int child : model.nodes[n].children) parent[static_cast<size_t>(child)] = static_cast<int>(n);
    std::map<int, glm::dmat4> placements;  // by skin: a chain of nodes sharing one skin walked it once each
    auto skinnedPlacement = [&](const tinygltf::Skin& skin, int skinIndex) {
        const auto known = placements.find(skinIndex);
        if (known != placements.end()) return known->second;
        glm::dmat4 world(1.0);
        for (int n = skin.joints[0]; n >= 0; n = parent[static_cast<size_t>(n)])
            world = localTransform(context, n) * world;
        glm::dmat4 inverseBind(1.0);
        if (skin.inverseBindMatrices >= 0) {
            const std::vector<float> first = context.accessors.readFloats(
                skin.inverseBindMatrices, 16, describe("skin", skinIndex, skin.name) + " inverseBindMatrices",
                1);
            for (int column = 0; column < 4; ++column)
                for (int row = 0; row < 4; ++row)
                    inverseBind[column][row] = first[static_cast<size_t>(4 * column + row)];
        }
        return placements[skinIndex] = world * inverseBind;
    };
    std::vector<Part> parts;
    auto add = [&](const glm::dvec3& centre, const glm::dvec3& halfSize) {
        if (std::isfinite(centre.x + centre.y + centre.z) &&
            std::isfinite(halfSize.x + halfSize.y + halfSize.z))
            parts.push_back({centre, halfSize});
    };
    // Depth first with a stack of its own: a hierarchy can be deeper than the call stack.
    std::vector<std::pair<int, glm::dmat4>> pending;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) pending.emplace_back(*root, glm::dmat4(1.0));
    while (!pending.empty()) {
        const auto [nodeIndex, parentWorld] = pending.back();
        pending.pop_back();
        const tinygltf::Node& node = model.nodes[nodeIndex];
        const glm::dmat4 world = parentWorld * localTransform(context, nodeIndex);
        // Each primitive's POSITION bounds.
        if (node.mesh >= 0 && node.mesh < static_cast<int>(model.meshes.size())) {
            const bool skinned = node.skin >= 0 && node.skin < static_cast<int>(model.skins.size()) &&
                                 !model.skins[static_cast<size_t>(node.skin)].joints.empty();
            const glm::dmat4 meshWorld =
                skinned ? skinnedPlacement(model.skins[static_cast<size_t>(node.skin)], node.skin) : world;
            for (const tinygltf::Primitive& primitive : model.meshes[node.mesh].primitives) {
                auto position = primitive.attributes.find("POSITION");
                if (position == primitive.attributes.end() || position->second < 0 ||
                    position->second >= static_cast<int>(model.accessors.size())) {
                    continue;
                }
                const tinygltf::Accessor& accessor = model.accessors[position->second];
                if (accessor.minValues.size() != 3 || accessor.maxValues.size() != 3) continue;
                // The bounds are the stored integers of a normalized accessor (KHR_mesh_quantization).
                glm::dvec4 centre(0.0, 0.0, 0.0, 1.0);
                glm::dvec3 half(0.0);
                for (int axis = 0; axis < 3; ++axis) {
                    const double low = normalizedValue(accessor.minValues[axis], accessor.componentType,
                                                       accessor.normalized);
                    const double high = normalizedValue(accessor.maxValues[axis], accessor.componentType,
                                                        accessor.normalized);
                    centre[axis] = 0.5 * (low + high);
                    half[axis] = 0.5 * std::abs(high - low);
                }
                add(glm::dvec3(meshWorld * centre), worldHalfSize(meshWorld, half));
            }
        }
        // A sphere of its radius, a shape of its canonical [-1, 1]^3, about the node's origin.
        if (auto sphere = node.extensions.find("VKRT_sphere"); sphere != node.extensions.end()) {
            const tinygltf::Value& radius = sphere->second.Get("radius");
            const double r = radius.IsNumber() ? std::abs(radius.GetNumberAsDouble()) : 0.0;
            add(glm::dvec3(world[3]), worldHalfSize(world, glm::dvec3(r)));
        }
        if (node.extensions.count("VKRT_shape"))
            add(glm::dvec3(world[3]), worldHalfSize(world, glm::dvec3(1.0)));
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
            pending.emplace_back(*child, world);
    }
    if (parts.empty()) return glm::dvec3(0.0);
    // Parts far larger than the typical one (a ground sphere or plane under the objects) stand for the point
    // of their box nearest the others' median, not for their centre, which can lie far from everything seen:
    // with two parts, a median of centres is the ground's.
    std::vector<double> sizes(parts.size());
    for (size_t i = 0; i < parts.size(); ++i) sizes[i] = parts[i].size();
    const auto middle = sizes.begin() + static_cast<std::ptrdiff_t>((sizes.size() - 1) / 2);
    std::nth_element(sizes.begin(), middle, sizes.end());
    const double large = 64.0 * *middle;
    std::vector<glm::dvec3> typical;
    for (const Part& part : parts)
        if (part.size() <= large) typical.push_back(part.centre);
    const glm::dvec3 typicalMedian = medianOf(typical);  // never empty: the median part is typical
    std::vector<glm::dvec3> representatives;
    for (const Part& part : parts) {
        representatives.push_back(
            part.size() <= large
                ? part.centre
                : glm::clamp(typicalMedian, part.centre - part.halfSize, part.centre + part.halfSize));
    }
    return medianOf(representatives);
}

}  // namespace vkrt
