#include "scene/gltf_solids.h"

#include <cmath>
#include <string>

#include <tiny_gltf.h>

#include "scene/gltf_materials.h"
#include "scene/scene_builder.h"
#include "shape_geometry.h"

namespace vkrt {
namespace {

enum class Operation { Shape, Union, Intersection, Difference };

// A node of a solid's expression: a shape, or an operation over other nodes.
struct Operand {
    Operation operation = Operation::Shape;
    uint32_t shape = 0;         // of the solid's shapes, for Operation::Shape
    std::vector<int> children;  // indices into SolidBuilder::operands_
};

constexpr int kMaxCsgDepth = 32;

class SolidBuilder {
  public:
    SolidBuilder(GltfContext& context, const LocalPoses& localPoses, int root)
        : context_(context),
          localPoses_(localPoses),
          rootWhere_(describe("node", root, context.model.nodes[root].name)) {}

    // Adds node `nodeIndex` (placed by `poses`) to the expression; returns its operand.
    int add(int nodeIndex, const std::vector<glm::dmat4>& poses, int depth);
    // Appends the solid to the scene (or warns that it is empty).
    void finish(int root);

  private:
    bool inside(int operand, uint32_t state) const;
    Aabb bounds(int operand) const;  // over the shutter
    Shape placeShape(const tinygltf::Value& extension, const glm::dmat4& world, const std::string& where);

    GltfContext& context_;
    const LocalPoses& localPoses_;
    std::string rootWhere_;
    std::vector<Operand> operands_;
    std::vector<Shape> shapes_;
    std::vector<std::vector<glm::mat4>> poses_;  // each shape's object-to-world map at each pose time
};

// VKRT_SHAPE_* by name; false for a name that is none.
bool shapeType(const std::string& name, uint32_t& type) {
    const std::pair<const char*, uint32_t> names[] = {{"sphere", VKRT_SHAPE_SPHERE},
                                                      {"box", VKRT_SHAPE_BOX},
                                                      {"cylinder", VKRT_SHAPE_CYLINDER},
                                                      {"cone", VKRT_SHAPE_CONE}};
    for (const auto& [known, value] : names) {
        if (name == known) {
            type = value;
            return true;
        }
    }
    return false;
}

Shape SolidBuilder::placeShape(const tinygltf::Value& extension, const glm::dmat4& world,
                               const std::string& where) {
    const std::string shapeWhere = where + " VKRT_shape";
    Shape shape{};
    if (!extension.IsObject() || !extension.Has("shape") || !extension.Get("shape").IsString() ||
        !shapeType(extension.Get("shape").Get<std::string>(), shape.type)) {
        context_.fail(shapeWhere + ": shape must be \"sphere\", \"box\", \"cylinder\" or \"cone\"");
    }
    if (!extension.Has("material")) {
        shape.material = defaultMaterial(context_);
    } else {
        const tinygltf::Value& value = extension.Get("material");
        if (!value.IsInt() || value.GetNumberAsInt() < 0 ||
            value.GetNumberAsInt() >= static_cast<int>(context_.model.materials.size())) {
            context_.fail(shapeWhere + ": material must be the index of a material");
        }
        shape.material = static_cast<uint32_t>(value.GetNumberAsInt());
    }
    // The map as the renderers store it (float), which must be finite and invertible.
    shape.toWorld = glm::mat4(world);
    const glm::dmat4 stored(shape.toWorld);
    const glm::dmat3 linear(stored);
    const double x = glm::length(linear[0]), y = glm::length(linear[1]), z = glm::length(linear[2]);
    const double determinant = glm::determinant(linear);
    bool finite = std::isfinite(determinant) && std::max({x, y, z}) < 1e30;
    for (int c = 0; c < 4; ++c) finite = finite && std::isfinite(stored[c].x + stored[c].y + stored[c].z);
    if (!finite) context_.fail(shapeWhere + ": the placed shape is not finite");
    // Flat: the volume the axes span against the product of their lengths, 1 for any orthogonal map whatever
    // its scales (a rod 1e8 times longer than it is thick is no harder to trace than a cube), near 0 where
    // the axes are near a plane (measured against the largest scale cubed, rods of aspect 1e6 were refused as
    // singular).
    if (!(std::abs(determinant) > 1e-6 * x * y * z))
        context_.fail(shapeWhere + ": the node transform is singular (it flattens the shape)");
    // Below 1e-30 a float map's entries lose their digits (1e-39 is a denormal of a few bits).
    if (!(std::min({x, y, z}) >= 1e-30))
        context_.fail(shapeWhere + ": the node transform scales the shape below 1e-30");
    shape.toObject = glm::inverse(stored);
    return shape;
}

int SolidBuilder::add(int nodeIndex, const std::vector<glm::dmat4>& poses, int depth) {
    const tinygltf::Node& node = context_.model.nodes[nodeIndex];
    const std::string where = describe("node", nodeIndex, node.name);
    const auto shape = node.extensions.find("VKRT_shape");
    const auto csg = node.extensions.find("VKRT_csg");
    if (shape != node.extensions.end() && csg != node.extensions.end())
        context_.fail(where + " has both VKRT_shape and VKRT_csg");
    if (depth > 0) {
        if (shape == node.extensions.end() && csg == node.extensions.end())
            context_.fail(where + " is a VKRT_csg operand without VKRT_shape or VKRT_csg");
        if (node.mesh >= 0 || node.camera >= 0 || node.extensions.count("KHR_lights_punctual") ||
            node.extensions.count("VKRT_sphere")) {
            context_.fail(
                where +
                " is a VKRT_csg operand, which holds only a shape (no mesh, camera, light or sphere)");
        }
    }
    if (depth > kMaxCsgDepth)
        context_.fail(rootWhere_ + " VKRT_csg: nested deeper than " + std::to_string(kMaxCsgDepth));
    Operand operand;
    if (shape != node.extensions.end()) {
        if (depth > 0 && !node.children.empty())
            context_.fail(where + " is a VKRT_csg operand shape with children");
        operand.shape = static_cast<uint32_t>(shapes_.size());
        shapes_.push_back(placeShape(shape->second, poses[0], where));
        std::vector<glm::mat4> placed;
        for (const glm::dmat4& pose : poses) placed.push_back(glm::mat4(pose));
        for (size_t k = 1; k < poses.size(); ++k)
            placeShape(shape->second, poses[k], where);  // each pose is valid
        poses_.push_back(std::move(placed));
    } else {
        const tinygltf::Value& extension = csg->second;
        const std::string name =
            extension.IsObject() && extension.Has("operation") && extension.Get("operation").IsString()
                ? extension.Get("operation").Get<std::string>()
                : "";
        if (name == "union")
            operand.operation = Operation::Union;
        else if (name == "intersection")
            operand.operation = Operation::Intersection;
        else if (name == "difference")
            operand.operation = Operation::Difference;
        else
            context_.fail(where +
                          " VKRT_csg: operation must be \"union\", \"intersection\" or \"difference\"");
        if (node.children.empty()) context_.fail(where + " VKRT_csg has no operands (child nodes)");
        for (int child : node.children) {
            const std::vector<glm::dmat4> local = localPoses_(child);
            std::vector<glm::dmat4> childPoses(poses.size());
            for (size_t k = 0; k < poses.size(); ++k) childPoses[k] = poses[k] * local[k];
            operand.children.push_back(add(child, childPoses, depth + 1));
            if (shapes_.size() > VKRT_CSG_MAX_SHAPES) {
                context_.fail(rootWhere_ + " VKRT_csg: more than " + std::to_string(VKRT_CSG_MAX_SHAPES) +
                              " shapes, the limit is " + std::to_string(VKRT_CSG_MAX_SHAPES));
            }
        }
    }
    operands_.push_back(std::move(operand));
    return static_cast<int>(operands_.size()) - 1;
}

bool SolidBuilder::inside(int index, uint32_t state) const {
    const Operand& operand = operands_[index];
    switch (operand.operation) {
        case Operation::Shape:
            return ((state >> operand.shape) & 1u) != 0u;
        case Operation::Union:
            for (int child : operand.children)
                if (inside(child, state)) return true;
            return false;
        case Operation::Intersection:
            for (int child : operand.children)
                if (!inside(child, state)) return false;
            return true;
        case Operation::Difference:
            for (size_t i = 1; i < operand.children.size(); ++i)
                if (inside(operand.children[i], state)) return false;
            return inside(operand.children[0], state);
    }
    return false;
}

Aabb SolidBuilder::bounds(int index) const {
    const Operand& operand = operands_[index];
    if (operand.operation == Operation::Shape) {
        // Over the shutter: a shape between two poses is a blend of them, inside their boxes' hull.
        Aabb swept;
        for (const glm::mat4& pose : poses_[operand.shape])
            swept.grow(shapeBounds(shapes_[operand.shape].type, pose));
        return swept;
    }
    if (operand.operation == Operation::Difference) return bounds(operand.children[0]);
    // An intersection of what each operand sweeps over the shutter, not of the poses' boxes pose by pose: two
    // shapes that meet only between two poses have an empty intersection at both.
    Aabb result = bounds(operand.children[0]);
    for (size_t i = 1; i < operand.children.size(); ++i) {
        const Aabb b = bounds(operand.children[i]);
        if (operand.operation == Operation::Union) {
            result.grow(b);
        } else {
            result.min = glm::max(result.min, b.min);
            result.max = glm::min(result.max, b.max);
        }
    }
    return result;
}

void SolidBuilder::finish(int root) {
    Scene& scene = context_.scene;
    Solid solid;
    solid.firstShape = static_cast<uint32_t>(scene.shapes.size());
    solid.shapeCount = static_cast<uint32_t>(shapes_.size());
    solid.table = truthTable(solid.shapeCount, [&](uint32_t state) { return inside(root, state); });
    const Aabb b = bounds(root);
    if (!b.empty()) solid.bounds = b;
    if (solid.bounds.empty() || solid.table == std::array<uint32_t, 8>{}) {
        context_.warn(rootWhere_ + ": the solid is empty; it is left out");
        return;
    }
    for (size_t i = 0; i < shapes_.size(); ++i) {
        scene.shapes.push_back(shapes_[i]);
        for (size_t k = 1; k < poses_[i].size(); ++k) scene.shapePoses.push_back(poses_[i][k]);
    }
    scene.solids.push_back(solid);
}

}  // namespace

bool hasSolid(const tinygltf::Node& node) {
    return node.extensions.count("VKRT_shape") > 0 || node.extensions.count("VKRT_csg") > 0;
}

bool isCsg(const tinygltf::Node& node) {
    return node.extensions.count("VKRT_csg") > 0;
}

void addSolid(GltfContext& context, int nodeIndex, const std::vector<glm::dmat4>& poses,
              const LocalPoses& localPoses) {
    SolidBuilder builder(context, localPoses, nodeIndex);
    const int root = builder.add(nodeIndex, poses, 0);
    builder.finish(root);
}

}  // namespace vkrt
