#include "scene/gltf_nodes.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>

#include <tiny_gltf.h>

#include "scene/gltf_accessors.h"
#include "scene/gltf_transforms.h"
#include "scene/scene_error.h"

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

// A part of the scene as approximateCenter sees it: a mesh primitive, a sphere or a shape, as the world box
// around it, the point that stands for it (a box's centre, or the median of a primitive's vertices) and the
// half-size of its core (a box's half-size, or its vertices' median distance from that median on the axis
// where that is largest: a few far vertices do not make it large).
struct Part {
    glm::dvec3 centre;
    glm::dvec3 low, high;
    double core = 0.0;
    double size() const { return 0.5 * std::max({high.x - low.x, high.y - low.y, high.z - low.z}); }
};

// The world half-size of a local box of half-size `half` under `world`'s linear part.
glm::dvec3 worldHalfSize(const glm::dmat4& world, const glm::dvec3& half) {
    glm::dvec3 result(0.0);
    for (int column = 0; column < 3; ++column) result += glm::abs(glm::dvec3(world[column])) * half[column];
    return result;
}

// Per axis, the median of `points`: for an even count the lower of the middle two, or, `averaged`, their
// mean (a rectangle's four corners have their centre as their median).
glm::dvec3 medianOf(const std::vector<glm::dvec3>& points, bool averaged = false) {
    glm::dvec3 median;
    std::vector<double> values(points.size());
    for (int axis = 0; axis < 3; ++axis) {
        for (size_t i = 0; i < points.size(); ++i) values[i] = points[i][axis];
        const auto middle = values.begin() + static_cast<std::ptrdiff_t>((values.size() - 1) / 2);
        std::nth_element(values.begin(), middle, values.end());
        median[axis] = *middle;
        if (averaged && values.size() % 2 == 0)
            median[axis] += 0.5 * (*std::min_element(middle + 1, values.end()) - *middle);
    }
    return median;
}

// The vertices approximateCenter reads of a primitive, at most: enough for a median that a few stray
// vertices do not move, few enough that a million-vertex mesh costs nothing.
constexpr size_t kCentreSamples = 4096;

// A mesh primitive's part in its mesh's frame: the median of (a sample of) its vertices, which a few far
// triangles do not move where they stretch its bounds (one triangle 1e17 away, in the same primitive as
// thousands of small ones, put the middle at 5e16 and the small ones, stored in float about it, vanished),
// in the box of its POSITION bounds, or of the vertices read where the file gives none. Nothing where the
// positions do not read: the walk reports why.
std::optional<Part> primitivePart(const GltfContext& context, int positionAccessor) {
    std::vector<float> values;
    try {
        values = context.accessors.sampleFloats(positionAccessor, 3, "POSITION", kCentreSamples);
    } catch (const SceneError&) {
        return std::nullopt;
    }
    std::vector<glm::dvec3> points;
    for (size_t i = 0; i + 2 < values.size(); i += 3) {
        const glm::dvec3 p(values[i], values[i + 1], values[i + 2]);
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) points.push_back(p);
    }
    if (points.empty()) return std::nullopt;
    Part part{medianOf(points, true), points[0], points[0]};
    std::vector<glm::dvec3> deviations;
    for (const glm::dvec3& p : points) deviations.push_back(glm::abs(p - part.centre));
    const glm::dvec3 spread = medianOf(deviations, true);
    part.core = std::max({spread.x, spread.y, spread.z});
    const tinygltf::Accessor& accessor = context.model.accessors[static_cast<size_t>(positionAccessor)];
    if (accessor.minValues.size() == 3 && accessor.maxValues.size() == 3) {
        // The bounds are the stored integers of a normalized accessor (KHR_mesh_quantization).
        for (int axis = 0; axis < 3; ++axis) {
            part.low[axis] =
                normalizedValue(accessor.minValues[axis], accessor.componentType, accessor.normalized);
            part.high[axis] =
                normalizedValue(accessor.maxValues[axis], accessor.componentType, accessor.normalized);
        }
    } else {
        for (const glm::dvec3& p : points) {
            part.low = glm::min(part.low, p);
            part.high = glm::max(part.high, p);
        }
    }
    part.centre = glm::clamp(part.centre, glm::min(part.low, part.high), glm::max(part.low, part.high));
    return part;
}

// `part` under `world`: its point mapped, its box the world box around the mapped one.
Part placed(const Part& part, const glm::dmat4& world) {
    const glm::dvec3 middle = 0.5 * (part.low + part.high);
    const glm::dvec3 half = worldHalfSize(world, 0.5 * glm::abs(part.high - part.low));
    const glm::dvec3 centre = glm::dvec3(world * glm::dvec4(middle, 1.0));
    double stretch = 0.0;  // the longest of its axes mapped: the factor of a uniform scale
    for (int column = 0; column < 3; ++column)
        stretch = std::max(stretch, glm::length(glm::dvec3(world[column])));
    return {glm::dvec3(world * glm::dvec4(part.centre, 1.0)), centre - half, centre + half,
            stretch * part.core};
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
    auto add = [&](const Part& part) {
        const glm::dvec3 sum = part.centre + part.low + part.high;
        if (std::isfinite(sum.x + sum.y + sum.z) && std::isfinite(part.size()) && std::isfinite(part.core))
            parts.push_back(part);
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
                if (const std::optional<Part> part = primitivePart(context, position->second))
                    add(placed(*part, meshWorld));
            }
        }
        // A sphere of its radius, a shape of its canonical [-1, 1]^3, about the node's origin.
        if (auto sphere = node.extensions.find("VKRT_sphere"); sphere != node.extensions.end()) {
            const tinygltf::Value& radius = sphere->second.Get("radius");
            const double r = radius.IsNumber() ? std::abs(radius.GetNumberAsDouble()) : 0.0;
            add(placed({glm::dvec3(0.0), glm::dvec3(-r), glm::dvec3(r), r}, world));
        }
        if (node.extensions.count("VKRT_shape"))
            add(placed({glm::dvec3(0.0), glm::dvec3(-1.0), glm::dvec3(1.0), 1.0}, world));
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
        representatives.push_back(part.size() <= large ? part.centre
                                                       : glm::clamp(typicalMedian, part.low, part.high));
    }
    glm::dvec3 centre = medianOf(representatives);
    // On each axis, the centre on a grid of a power of two: at most float's spacing at the scene's farthest
    // coordinate there, and at most about a quarter of the typical part's core, so that the parts stay as
    // near the origin as they were. A float coordinate is a whole number of its own spacing, so moving one
    // whose spacing is the grid's or finer by the centre is exact wherever the result lies no farther out
    // than it did: the file's vertices keep their positions. Off the grid, a triangle reaching 1e9 beside a
    // floor of 1e3, re-centred about a corner of the floor, had its corners rounded by up to 32 and its edge
    // over the camera moved, and the double-precision reference rendered another scene.
    std::vector<double> cores(parts.size());
    for (size_t i = 0; i < parts.size(); ++i) cores[i] = parts[i].core;
    const auto typicalCore = cores.begin() + static_cast<std::ptrdiff_t>((cores.size() - 1) / 2);
    std::nth_element(cores.begin(), typicalCore, cores.end());
    if (*typicalCore > 0.0) {
        for (int axis = 0; axis < 3; ++axis) {
            double farthest = 0.0;
            for (const Part& part : parts)
                farthest = std::max({farthest, std::abs(part.low[axis]), std::abs(part.high[axis])});
            // The coarsest spacing allowed: float's at 2^22 typical cores, or at the farthest coordinate.
            int exponent = 0;
            std::frexp(std::min(farthest, 0x1p22 * *typicalCore), &exponent);
            const double spacing = std::ldexp(1.0, exponent - std::numeric_limits<float>::digits);
            if (spacing > 0.0) centre[axis] = std::round(centre[axis] / spacing) * spacing;
        }
    }
    // Every part's box stays within float's range about the centre (a triangle with corners near float's
    // range, about one of them, would reach past it), where it can.
    constexpr double kRoom = 0.999 * std::numeric_limits<float>::max();
    glm::dvec3 lowest(-std::numeric_limits<double>::infinity()),
        highest(std::numeric_limits<double>::infinity());
    for (const Part& part : parts) {
        lowest = glm::max(lowest, part.high - kRoom);
        highest = glm::min(highest, part.low + kRoom);
    }
    for (int axis = 0; axis < 3; ++axis)
        if (lowest[axis] <= highest[axis])
            centre[axis] = std::clamp(centre[axis], lowest[axis], highest[axis]);
    return centre;
}

}  // namespace vkrt
