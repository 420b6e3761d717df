#include "scene/gltf_loader.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/memory_need.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_cameras.h"
#include "scene/gltf_compression.h"
#include "scene/gltf_context.h"
#include "scene/gltf_extensions.h"
#include "scene/gltf_images.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_nodes.h"
#include "scene/gltf_primitives.h"
#include "scene/gltf_schema.h"
#include "scene/gltf_solids.h"
#include "scene/gltf_texture_slots.h"
#include "scene/gltf_transforms.h"
#include "scene/scene_builder.h"

namespace vkrt {
namespace {

// The index of the animation that plays (LoadOptions::animation): -1 where the file has none.
int chooseAnimation(GltfContext& context, const std::string& request) {
    const std::vector<tinygltf::Animation>& animations = context.model.animations;
    const auto named = [&](size_t a) {
        return animations[a].name.empty()
                   ? "animation " + std::to_string(a)
                   : "animation " + std::to_string(a) + " (\"" + animations[a].name + "\")";
    };
    if (request.empty()) {
        if (animations.empty()) return -1;
        if (animations.size() > 1) {
            context.warn("the file has " + std::to_string(animations.size()) + " animations; " + named(0) +
                         " plays (--animation picks another)");
        }
        return 0;
    }
    for (size_t a = 0; a < animations.size(); ++a)
        if (animations[a].name == request) return static_cast<int>(a);
    const bool digits = request.find_first_not_of("0123456789") == std::string::npos && request.size() < 10;
    if (digits && std::stoul(request) < animations.size()) return static_cast<int>(std::stoul(request));
    std::string names;
    for (size_t a = 0; a < animations.size(); ++a) names += (a == 0 ? "" : ", ") + named(a);
    context.fail("--animation " + request + ": no such animation (the file has " +
                 (animations.empty() ? std::string("none") : names) + ")");
}

// The conversion of one model: materials first, then a walk of the node graph that places meshes,
// cameras, lights and spheres in the world.
class GltfConverter {
  public:
    GltfConverter(const tinygltf::Model& model, std::string path, const LoadOptions& options,
                  ImageFailures imageFailures, uint64_t imageBytes, std::optional<std::set<int>> placed)
        : context_(model, std::move(path)),
          options_(options),
          selectedAnimation_(chooseAnimation(context_, options.animation)),
          meshes_(context_) {
        context_.imageFailures = std::move(imageFailures);
        context_.placedMaterials = std::move(placed);
        otherBytes_ = imageBytes;  // the decoded images share the memory with the triangles
    }

    Scene convert();

  private:
    // A node's world transform at the shutter's opening and at the end of each motion segment.
    using Poses = std::vector<glm::dmat4>;

    void chooseShutter();
    // Fails where a surface uses a material that placedMaterials, which chose the textures read, missed.
    void checkPlacedMaterialsWereRead() const;
    // Places the tree under `root` in the world, below `parents`.
    void walk(int root, const Poses& parents);
    // Places one node's mesh, camera, light, sphere and solid; returns its poses, its children's parents.
    Poses place(int nodeIndex, const Poses& parents);
    // Counts `instances` more placements of mesh `meshIndex` against the host memory the options allow,
    // before any of them is placed.
    void reserveTriangles(int meshIndex, uint64_t instances, const std::string& where);
    // Counts `bytes` more of host memory for `what` against what the options allow, checking first that
    // `passingBytes` more fit beside them for a moment (what reading them takes and frees).
    void reserveBytes(uint64_t bytes, const std::string& what, uint64_t passingBytes = 0);
    // Checks that `bytes` that a primitive holds while it is decoded fit beside the triangles placed so far
    // and the other memory counted (those reserved but not yet placed take nothing yet).
    void checkDecoding(uint64_t bytes, const std::string& what) const;
    // Throws MemoryError when `bytes` more for `what` do not fit beside the `held` bytes.
    void refuseUnlessAvailable(double held, uint64_t bytes, const std::string& what) const;
    // The host memory each placed triangle keeps (chooseTriangleBytes).
    void chooseTriangleBytes();
    // Where the mesh of node `nodeIndex`, whose world transforms are `poses`, is at each pose time: with its
    // morph targets' weights and, when the node has a skin, its joints' matrices.
    std::vector<InstancePose> meshPoses(int nodeIndex, const Poses& poses, const std::string& where);
    // The node's morph-target weights at rest: its own, else its mesh's, else zero (glTF 2.0 3.7.2.2).
    std::vector<double> restWeights(int nodeIndex, const std::string& where) const;
    // Which morph targets of each mesh some node weighs (at rest or by an animation), and which meshes some
    // node skins: only their targets, and their joints and weights, are read.
    void markDeformations();
    // A node's world transform at each pose time (a skin's joints can be anywhere in the graph).
    const Poses& worldOf(int nodeIndex);
    // A skin's joint matrices at each pose time: each joint's world transform times its inverse bind matrix
    // (the identity where the skin gives none).
    const std::vector<std::vector<glm::dmat4>>& skinJoints(int skinIndex);

    GltfContext context_;
    LoadOptions options_;
    int selectedAnimation_;      // the animation that plays, -1 for none
    NodeAnimations animations_;  // read by convert(), once the images are counted
    MeshInstancer meshes_;
    std::vector<double> poseTimes_;  // the shutter's opening, then the end of each motion segment
    uint64_t triangleBound_ = 0;     // the most triangles the meshes placed so far can have
    uint64_t triangleBytes_ = sizeof(Triangle) + sizeof(TriangleShading);  // chooseTriangleBytes
    uint64_t otherBytes_ = 0;        // host memory beside the triangles: images, skins' joints, deformations
    glm::dmat4 recentre_{1.0};       // the world's translation that puts the scene's centre at the origin
    std::vector<int> parents_;       // each node's parent, -1 for none (filled when first needed)
    std::map<int, Poses> worlds_;    // world transforms of the joints and their ancestors, by node
    std::map<int, std::vector<std::vector<glm::dmat4>>> skinJoints_;  // by skin: per pose, per joint
    std::map<int, std::vector<bool>> liveTargets_;                    // by mesh: per morph target
    std::set<int> skinnedMeshes_;                                     // meshes some node skins
};

// The most triangles a mesh's primitives can make, from their accessors' counts (zero for what the decoder
// will refuse or skip).
uint64_t triangleBound(const tinygltf::Model& model, const tinygltf::Mesh& mesh) {
    uint64_t bound = 0;
    for (const tinygltf::Primitive& primitive : mesh.primitives) {
        const auto position = primitive.attributes.find("POSITION");
        const int accessor = primitive.indices >= 0                   ? primitive.indices
                             : position != primitive.attributes.end() ? position->second
                                                                      : -1;
        if (accessor < 0 || accessor >= static_cast<int>(model.accessors.size())) continue;
        const uint64_t count = model.accessors[static_cast<size_t>(accessor)].count;
        if (primitive.mode == TINYGLTF_MODE_TRIANGLES) bound += count / 3;
        if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP || primitive.mode == TINYGLTF_MODE_TRIANGLE_FAN)
            bound += count > 2 ? count - 2 : 0;
    }
    return bound;
}

Scene GltfConverter::convert() {
    Scene& scene = context_.scene;
    scene.sourcePath = context_.path;
    animations_ = NodeAnimations(context_.model, context_.accessors, context_.path, selectedAnimation_,
                                 [this](uint64_t keptBytes, uint64_t passingBytes, const std::string& what) {
                                     reserveBytes(keptBytes, what, passingBytes);
                                 });
    checkExtensions(context_);
    convertMaterials(context_);
    convertTextures(context_);

    std::vector<int> roots = sceneRoots(context_);
    checkNodeGraph(context_, roots);
    // Walk with the scene's approximate centre moved to the origin (re-centring keeps float precision).
    scene.origin = approximateCenter(context_, roots);
    recentre_ = glm::translate(glm::dmat4(1.0), -scene.origin);
    chooseShutter();
    chooseTriangleBytes();
    markDeformations();
    meshes_.setReserve([this](uint64_t bytes, const std::string& what) { reserveBytes(bytes, what); });
    meshes_.setDecodingCheck([this](uint64_t bytes, const std::string& what) { checkDecoding(bytes, what); });
    for (int root : roots) walk(root, Poses(poseTimes_.size(), recentre_));
    checkPlacedMaterialsWereRead();
    meshes_.warnAboutSkipped();
    if (scene.triangles.empty() && scene.spheres.empty() && scene.solids.empty())
        context_.warn("the scene has no triangles, spheres or shapes");

    finalizeScene(scene);
    return std::move(scene);
}

void GltfConverter::checkPlacedMaterialsWereRead() const {
    if (!context_.placedMaterials) return;
    const Scene& scene = context_.scene;
    std::vector<bool> read(scene.materials.size(), true);  // glTF's default material is read when used
    for (size_t i = 0; i < context_.model.materials.size(); ++i)
        read[i] = context_.placedMaterials->count(static_cast<int>(i)) != 0;
    const auto check = [&](uint32_t material) {
        if (material < read.size() && !read[material])
            context_.fail(describe("material", static_cast<int>(material), scene.materials[material].name) +
                          " is placed but its textures were not read (vkrt's walk of the file's nodes missed "
                          "it)");
    };
    for (const Triangle& triangle : scene.triangles) check(triangle.material);
    for (const Sphere& sphere : scene.spheres) check(sphere.material);
    for (const Shape& shape : scene.shapes) check(shape.material);
}

// The shutter interval: the caller's, else the scene's extras {"shutter": [open, close]} (seconds of the
// file's animation timeline), else closed at 0.
void GltfConverter::chooseShutter() {
    const tinygltf::Model& model = context_.model;
    Scene& scene = context_.scene;
    if (options_.shutter) {
        scene.shutterOpen = (*options_.shutter)[0];
        scene.shutterClose = (*options_.shutter)[1];
        if (model.animations.empty() && scene.shutterClose > scene.shutterOpen)
            context_.warn(
                "--shutter: the file has no animations, so nothing moves while the shutter is open");
    } else if (!model.scenes.empty()) {
        const tinygltf::Value& extras = model.scenes[std::max(0, model.defaultScene)].extras;
        if (extras.IsObject() && extras.Has("shutter")) {
            // Not two numbers: another application's (extras are everyone's), passed over with a warning.
            const tinygltf::Value& shutter = extras.Get("shutter");
            if (!shutter.IsArray() || shutter.ArrayLen() != 2 || !shutter.Get(0).IsNumber() ||
                !shutter.Get(1).IsNumber()) {
                context_.warn("the scene's extras.shutter is not [open, close]; it is ignored");
            } else {
                scene.shutterOpen = shutter.Get(0).GetNumberAsDouble();
                scene.shutterClose = shutter.Get(1).GetNumberAsDouble();
            }
        }
    }
    if (!std::isfinite(scene.shutterOpen) || !std::isfinite(scene.shutterClose) ||
        scene.shutterClose < scene.shutterOpen) {
        context_.fail("the shutter must close at or after it opens");
    }
    // Motion segments: one when everything moves by linear translation alone (exact), else
    // kMotionSegments, whose poses follow rotations, curves and steps within the shutter.
    poseTimes_ = {scene.shutterOpen};
    if (scene.shutterClose > scene.shutterOpen && !animations_.empty()) {
        scene.motionSegments =
            animations_.linearTranslationOnly(scene.shutterOpen, scene.shutterClose) ? 1 : kMotionSegments;
        for (int k = 1; k <= scene.motionSegments; ++k) {
            poseTimes_.push_back(scene.shutterOpen +
                                 (scene.shutterClose - scene.shutterOpen) * k / scene.motionSegments);
        }
    }
}

// Each triangle keeps its corners and material at each pose and its shading (normals, texture coordinates);
// the scene's tangent frames, vertex colours and second texture coordinates, once a primitive has them, cover
// every triangle (gltf_primitives.cpp's place), so where a material can map normals, a primitive has COLOR_0,
// or one has or reads a second set, every triangle is counted with them.
void GltfConverter::chooseTriangleBytes() {
    const tinygltf::Model& model = context_.model;
    bool tangents = false, colors = false, uv1 = false;
    for (const Material& material : context_.scene.materials) {
        tangents = tangents || material.tangentFrameSlot().used();
        for (const TextureSlot* slot : material.textureSlots())
            uv1 = uv1 || (slot->used() && slot->texCoord == 1);
    }
    for (const tinygltf::Mesh& mesh : model.meshes) {
        for (const tinygltf::Primitive& primitive : mesh.primitives) {
            colors = colors || primitive.attributes.count("COLOR_0") > 0;
            uv1 = uv1 || primitive.attributes.count("TEXCOORD_1") > 0;
        }
    }
    triangleBytes_ = sizeof(Triangle) * poseTimes_.size() + sizeof(TriangleShading);
    if (tangents) triangleBytes_ += sizeof(std::array<glm::vec4, 3>);
    if (colors) triangleBytes_ += sizeof(std::array<glm::vec4, 3>);
    if (uv1) triangleBytes_ += sizeof(std::array<glm::vec2, 3>);
}

void GltfConverter::reserveTriangles(int meshIndex, uint64_t instances, const std::string& where) {
    const uint64_t limit =
        (options_.maxSceneBytes - std::min(options_.maxSceneBytes, otherBytes_)) / triangleBytes_;
    const uint64_t bound =
        triangleBound(context_.model, context_.model.meshes[static_cast<size_t>(meshIndex)]);
    if (bound > 0 && instances > (limit - std::min(limit, triangleBound_)) / bound) {
        const double total =
            static_cast<double>(triangleBound_) + static_cast<double>(bound) * static_cast<double>(instances);
        const double bytes = std::min(total * static_cast<double>(triangleBytes_), 1.8e19);
        char count[32];
        std::snprintf(count, sizeof count, "%.3g", total);
        throw MemoryError(context_.path + ": " + where + " places mesh " + std::to_string(meshIndex) + " " +
                          std::to_string(instances) + " time(s): the scene would hold up to " + count +
                          " triangles, about " + formatBytes(static_cast<uint64_t>(bytes)) +
                          " of host memory, and " + formatBytes(options_.maxSceneBytes) + " is available (" +
                          options_.memorySource + ")");
    }
    triangleBound_ += bound * instances;
}

void GltfConverter::walk(int root, const Poses& rootParents) {
    // Depth first, parents before children and children in order, with a stack of its own: a file's
    // hierarchy can be deeper than the call stack.
    std::vector<std::pair<int, Poses>> pending{{root, rootParents}};
    while (!pending.empty()) {
        auto [nodeIndex, parents] = std::move(pending.back());
        pending.pop_back();
        const Poses poses = place(nodeIndex, parents);
        const tinygltf::Node& node = context_.model.nodes[nodeIndex];
        if (isCsg(node)) continue;  // its children are its operands, placed with it
        const std::vector<int>& children = node.children;
        for (auto child = children.rbegin(); child != children.rend(); ++child) pending.emplace_back(*child, poses);
    }
}

GltfConverter::Poses GltfConverter::place(int nodeIndex, const Poses& parents) {
    const tinygltf::Node& node = context_.model.nodes[nodeIndex];
    // Compose the node's world transform at each pose time.
    Poses poses(parents.size());
    for (size_t k = 0; k < poses.size(); ++k)
        poses[k] = parents[k] * localTransformAt(context_, animations_, nodeIndex, poseTimes_[k]);
    const glm::dmat4& world = poses[0];
    const std::string where = describe("node", nodeIndex, node.name);
    // Place the node's mesh, once per EXT_mesh_gpu_instancing instance when it has them.
    if (node.mesh >= 0) {
        if (node.mesh >= static_cast<int>(context_.model.meshes.size())) {
            context_.fail(where + " refers to mesh " + std::to_string(node.mesh) + ", which does not exist");
        }
        auto instancing = node.extensions.find("EXT_mesh_gpu_instancing");
        const std::vector<InstancePose> meshAt = meshPoses(nodeIndex, poses, where);
        if (instancing == node.extensions.end()) {
            reserveTriangles(node.mesh, 1, where);
            meshes_.addInstance(node.mesh, meshAt);
        } else {
            const std::vector<glm::dmat4> instances = instanceTransforms(
                context_, instancing->second, where,
                [this](uint64_t bytes, const std::string& what) { checkDecoding(bytes, what); });
            // The instances' transforms are held beside their triangles while those are placed.
            const uint64_t transformBytes = instances.size() * sizeof(glm::dmat4);
            otherBytes_ += transformBytes;
            reserveTriangles(node.mesh, instances.size(), where);
            if (node.skin >= 0)
                context_.warn(where + ": the instances of a skinned mesh all follow its joints");
            for (const glm::dmat4& instance : instances) {
                std::vector<InstancePose> instanceAt = meshAt;
                for (InstancePose& pose : instanceAt) pose.world = pose.world * instance;
                meshes_.addInstance(node.mesh, instanceAt);
            }
            otherBytes_ -= transformBytes;
        }
    }
    // Place its camera, light and sphere.
    if (node.camera >= 0) addCamera(context_, node.camera, world, nodeIndex, node.name);
    auto light = node.extensions.find("KHR_lights_punctual");
    if (light != node.extensions.end()) addLight(context_, light->second, world, where);
    auto sphere = node.extensions.find("VKRT_sphere");
    if (sphere != node.extensions.end()) {
        std::vector<Sphere> placed;
        for (const glm::dmat4& pose : poses)
            placed.push_back(placeSphere(context_, sphere->second, pose, where));
        const auto vanishes = [](const Sphere& s) { return s.radius == 0.0f; };
        if (std::all_of(placed.begin(), placed.end(), vanishes)) {
            // Scaled to nothing throughout, as glTF hides a node: skipped, as a mesh's vanished triangles
            // are.
            context_.warn(where + " VKRT_sphere: the node scales it to nothing; it is skipped");
        } else if (std::any_of(placed.begin(), placed.end(), vanishes)) {
            context_.fail(where +
                          " VKRT_sphere: the node scales it to nothing within the shutter; an animated "
                          "sphere keeps a radius");
        } else {
            context_.scene.spheres.push_back(placed[0]);
            context_.scene.spherePoses.insert(context_.scene.spherePoses.end(), placed.begin() + 1,
                                              placed.end());
        }
    }
    if (hasSolid(node)) {
        addSolid(context_, nodeIndex, poses, [&](int child) {
            Poses local(poseTimes_.size());
            for (size_t k = 0; k < local.size(); ++k)
                local[k] = localTransformAt(context_, animations_, child, poseTimes_[k]);
            return local;
        });
    }
    return poses;
}

std::vector<InstancePose> GltfConverter::meshPoses(int nodeIndex, const Poses& poses,
                                                   const std::string& where) {
    const tinygltf::Model& model = context_.model;
    const tinygltf::Node& node = model.nodes[nodeIndex];
    std::vector<InstancePose> result(poses.size());
    const std::vector<double> rest = restWeights(nodeIndex, where);
    for (size_t k = 0; k < poses.size(); ++k) {
        result[k].world = poses[k];
        result[k].weights = animations_.evaluateWeights(nodeIndex, rest, poseTimes_[k]);
    }
    if (node.skin < 0) return result;
    if (node.skin >= static_cast<int>(model.skins.size()))
        context_.fail(where + " refers to skin " + std::to_string(node.skin) + ", which does not exist");
    const std::vector<std::vector<glm::dmat4>>& joints = skinJoints(node.skin);
    for (size_t k = 0; k < poses.size(); ++k) result[k].joints = &joints[k];
    return result;
}

std::vector<double> GltfConverter::restWeights(int nodeIndex, const std::string& where) const {
    const tinygltf::Model& model = context_.model;
    const tinygltf::Node& node = model.nodes[nodeIndex];
    const size_t targets = meshes_.morphTargetCount(node.mesh);
    const std::vector<double>& given = node.weights.empty() ? model.meshes[node.mesh].weights : node.weights;
    if (given.empty()) return std::vector<double>(targets, 0.0);
    if (given.size() != targets) {
        context_.fail(where + (node.weights.empty() ? "'s mesh" : "") + " has " +
                      std::to_string(given.size()) + " morph-target weight(s) for " +
                      std::to_string(targets) + " morph target(s)");
    }
    return given;
}

void GltfConverter::markDeformations() {
    const tinygltf::Model& model = context_.model;
    for (size_t n = 0; n < model.nodes.size(); ++n) {
        const tinygltf::Node& node = model.nodes[n];
        if (node.mesh < 0 || node.mesh >= static_cast<int>(model.meshes.size())) continue;
        if (node.skin >= 0) skinnedMeshes_.insert(node.mesh);
        const std::vector<double>& given =
            node.weights.empty() ? model.meshes[node.mesh].weights : node.weights;
        const bool animated = animations_.animatesWeights(static_cast<int>(n));
        std::vector<bool>& live = liveTargets_[node.mesh];
        live.resize(std::max(live.size(), meshes_.morphTargetCount(node.mesh)), false);
        for (size_t t = 0; t < live.size(); ++t)
            live[t] = live[t] || animated || (t < given.size() && given[t] != 0.0);
    }
    meshes_.setLiveTargets(&liveTargets_);
    meshes_.setSkinnedMeshes(&skinnedMeshes_);
}

void GltfConverter::reserveBytes(uint64_t bytes, const std::string& what, uint64_t passingBytes) {
    refuseUnlessAvailable(static_cast<double>(triangleBound_) * static_cast<double>(triangleBytes_) +
                              static_cast<double>(otherBytes_),
                          saturatedBytes(static_cast<double>(bytes) + static_cast<double>(passingBytes)),
                          what);
    otherBytes_ += bytes;
}

void GltfConverter::checkDecoding(uint64_t bytes, const std::string& what) const {
    refuseUnlessAvailable(
        static_cast<double>(context_.scene.triangles.size()) * static_cast<double>(triangleBytes_) +
            static_cast<double>(otherBytes_),
        bytes, what);
}

void GltfConverter::refuseUnlessAvailable(double held, uint64_t bytes, const std::string& what) const {
    if (held + static_cast<double>(bytes) > static_cast<double>(options_.maxSceneBytes)) {
        throw MemoryError(context_.path + ": " + what + " would take " + formatBytes(bytes) +
                          " of host memory beside the scene's " + formatBytes(static_cast<uint64_t>(held)) +
                          ", and " + formatBytes(options_.maxSceneBytes) + " is available (" +
                          options_.memorySource + ")");
    }
}

const GltfConverter::Poses& GltfConverter::worldOf(int nodeIndex) {
    const std::vector<tinygltf::Node>& nodes = context_.model.nodes;
    if (parents_.empty()) {
        parents_.assign(nodes.size(), -1);
        for (size_t n = 0; n < nodes.size(); ++n)
            for (int child : nodes[n].children) parents_[static_cast<size_t>(child)] = static_cast<int>(n);
    }
    // The chain up to a node already known or a root (the graph is a forest: checkNodeGraph), then down it.
    std::vector<int> chain;
    for (int n = nodeIndex; n >= 0 && !worlds_.count(n); n = parents_[static_cast<size_t>(n)])
        chain.push_back(n);
    for (auto n = chain.rbegin(); n != chain.rend(); ++n) {
        const int parent = parents_[static_cast<size_t>(*n)];
        Poses world(poseTimes_.size());
        for (size_t k = 0; k < world.size(); ++k) {
            world[k] = (parent < 0 ? recentre_ : worlds_.at(parent)[k]) *
                       localTransformAt(context_, animations_, *n, poseTimes_[k]);
        }
        worlds_.emplace(*n, std::move(world));
    }
    return worlds_.at(nodeIndex);
}

const std::vector<std::vector<glm::dmat4>>& GltfConverter::skinJoints(int skinIndex) {
    auto found = skinJoints_.find(skinIndex);
    if (found != skinJoints_.end()) return found->second;
    const tinygltf::Skin& skin = context_.model.skins[static_cast<size_t>(skinIndex)];
    const std::string where = describe("skin", skinIndex, skin.name);
    // The joints' world transforms and matrices at each pose, and their inverse bind matrices, before any is
    // made.
    reserveBytes(static_cast<uint64_t>(skin.joints.size()) * (2 * poseTimes_.size() + 1) * sizeof(glm::dmat4),
                 where + "'s " + std::to_string(skin.joints.size()) + " joints");
    std::vector<glm::dmat4> inverseBinds(skin.joints.size(), glm::dmat4(1.0));  // the identity where none
    if (skin.inverseBindMatrices >= 0) {
        const std::vector<float> values = context_.accessors.readFloats(
            skin.inverseBindMatrices, 16, where + " inverseBindMatrices", skin.joints.size());
        if (values.size() < 16 * inverseBinds.size()) {
            context_.fail(where + " has " + std::to_string(values.size() / 16) +
                          " inverse bind matrices for " + std::to_string(inverseBinds.size()) + " joints");
        }
        for (size_t j = 0; j < inverseBinds.size(); ++j) {
            for (int column = 0; column < 4; ++column) {
                for (int row = 0; row < 4; ++row) {
                    const float value = values[16 * j + 4 * column + row];  // column-major
                    if (!std::isfinite(value)) context_.fail(where + " has a non-finite inverse bind matrix");
                    inverseBinds[j][column][row] = value;
                }
            }
        }
    }
    // Each joint's world transform times its inverse bind matrix; the skinned node's own transform is not
    // applied to its skinned primitives (glTF 2.0 section 3.7.3.3).
    std::vector<std::vector<glm::dmat4>> joints(poseTimes_.size(),
                                                std::vector<glm::dmat4>(skin.joints.size()));
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const Poses& world = worldOf(skin.joints[j]);
        for (size_t k = 0; k < poseTimes_.size(); ++k) joints[k][j] = world[k] * inverseBinds[j];
    }
    return skinJoints_.emplace(skinIndex, std::move(joints)).first->second;
}

// tinygltf 2.7 refuses a skin without inverseBindMatrices, which glTF 2.0 makes optional (identity matrices,
// section 3.7.3.1): -1 tells it, and skinJoints, that there are none. True when the document changed.
bool markAbsentInverseBindMatrices(nlohmann::json& document) {
    if (!document.is_object() || !document.contains("skins") || !document["skins"].is_array()) return false;
    bool changed = false;
    for (nlohmann::json& skin : document["skins"]) {
        if (skin.is_object() && !skin.contains("inverseBindMatrices")) {
            skin["inverseBindMatrices"] = -1;
            changed = true;
        }
    }
    return changed;
}

// The scene file's bytes, read once, so that a named pipe (a shell's `<(...)`) loads as a file does: every
// later look (the GLB header, the JSON, tinygltf's parse) reads them from memory.
std::string readSceneFile(const std::string& path) {
    std::error_code statusError;
    if (std::filesystem::is_directory(path, statusError)) throw SceneError(path + ": is a directory");
    // tinygltf takes a document's length as 32 bits: a regular file is measured before it is read.
    const auto tooLarge = [&] { return SceneError(path + ": larger than 4 GiB, more than tinygltf reads"); };
    const std::uintmax_t size = std::filesystem::file_size(path, statusError);
    if (!statusError && size > std::numeric_limits<unsigned int>::max()) throw tooLarge();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open file");
    std::string bytes;
    if (!statusError) bytes.reserve(size);
    std::vector<char> chunk(1 << 20);
    while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
        bytes.append(chunk.data(), static_cast<size_t>(in.gcount()));
        if (bytes.size() > std::numeric_limits<unsigned int>::max())
            throw tooLarge();  // a pipe's, as it comes
        if (in.eof()) break;
    }
    if (in.bad()) throw SceneError(path + ": cannot read file");
    if (bytes.empty()) throw SceneError(path + ": the file is empty");
    return bytes;
}

// tinygltf's file reading, refusing what is not a regular file: a buffer or image whose URI names a
// directory had it read the directory's size as a file's and ask for that much memory. Each file read is
// listed in `files` (a std::vector<std::string>, the callbacks' user data).
bool readRegularFile(std::vector<unsigned char>* out, std::string* error, const std::string& path,
                     void* files) {
    std::error_code status;
    if (!std::filesystem::is_regular_file(path, status)) {
        if (error) *error += "File is not a regular file: " + path + "\n";
        return false;
    }
    static_cast<std::vector<std::string>*>(files)->push_back(path);
    return tinygltf::ReadWholeFile(out, error, path, nullptr);
}

// The GLB header's version (glTF 2.0, 4.4.2: version 2; version 1 was glTF 1.0's binary extension).
void checkGlbVersion(std::string_view file, const std::string& path) {
    if (file.size() < 8) throw SceneError(path + ": not a valid GLB file (its header is cut short)");
    const auto byte = [&](size_t i) { return static_cast<uint32_t>(static_cast<unsigned char>(file[i])); };
    const uint32_t version = byte(4) | byte(5) << 8 | byte(6) << 16 | byte(7) << 24;
    if (version != 2)
        throw SceneError(path + ": GLB version " + std::to_string(version) +
                         "; vkrt reads GLB version 2 (glTF 2.0)");
}

// The bytes of JSON text `json` outside its strings of more than 256 bytes.
uint64_t structuralJsonBytes(std::string_view json) {
    constexpr size_t kLongString = 256;
    uint64_t inLongStrings = 0;
    for (size_t i = 0; i < json.size(); ++i) {
        if (json[i] != '"') continue;
        size_t end = i + 1;
        while (end < json.size() && json[end] != '"') end += json[end] == '\\' ? 2 : 1;
        if (end - i > kLongString) inLongStrings += std::min(end, json.size()) - i;
        i = end;
    }
    return json.size() - inLongStrings;
}

// tinygltf's model of the file at `path` (its images decoded through `imageDecoding`; the files it refers to
// and read listed in `files`; the materials its scene places in `placed`, nullopt when unknown). The file's
// bytes and its JSON are let go on return, before the model is converted.
tinygltf::Model parseGltf(const std::string& path, const LoadOptions& options, ImageDecoding& imageDecoding,
                          std::vector<std::string>& files, std::optional<std::set<int>>& placed) {
    std::string file = readSceneFile(path);

    // The JSON first: a required extension vkrt lacks, then every property vkrt reads, checked for its type
    // and range (tinygltf skips what has the wrong type). JSON that does not parse is left to tinygltf to
    // describe.
    const bool binary = file.compare(0, 4, "glTF") == 0;
    if (binary) checkGlbVersion(file, path);
    // Parsing the JSON's structure takes about 20 times its text (a document of 100,000 lights' nodes, 28 MB,
    // peaked at 583 MB: vkrt's parse for its checks, then tinygltf's and its model), before anything else is
    // counted; long strings (a buffer's or an image's base64 data) are held once or twice as they are. Up to
    // 16 MiB the parse is part of the process's own footprint (vkrt alone takes about 12), which no estimate
    // counts either.
    constexpr uint64_t kParseBytesPerJsonByte = 21, kUncountedParseBytes = uint64_t(16) << 20;
    const uint64_t jsonBytes = structuralJsonBytes(gltfJsonText(file, binary).value_or(std::string_view()));
    if (jsonBytes > kUncountedParseBytes / kParseBytesPerJsonByte &&
        jsonBytes > options.maxSceneBytes / kParseBytesPerJsonByte) {
        throw MemoryError(
            path + ": parsing its " + formatBytes(jsonBytes) + " of JSON structure takes about " +
            formatBytes(jsonBytes * kParseBytesPerJsonByte) + " of host memory, and " +
            formatBytes(options.maxSceneBytes) + " is available (" + options.memorySource + ")");
    }
    nlohmann::json document = readGltfJson(file, binary);
    bool rewritten = false;
    if (!document.is_discarded()) {
        if (const auto extension = unsupportedRequiredExtension(document))
            throw SceneError(path + ": requires extension " + *extension + ", which vkrt does not support");
        validateGltfJson(document, path);
        rewritten = stubCompressedData(document);
        rewritten |= retypeImageDataUris(document);
        rewritten |= markAbsentInverseBindMatrices(document);
    }

    tinygltf::TinyGLTF reader;
    if (!document.is_discarded()) {
        // Only the textures of materials the scene places are decoded (a material no node uses is not read).
        placed = placedMaterials(document);
        imageDecoding.shown = shownImages(document, placed);
    }
    imageDecoding.maxBytes = options.maxSceneBytes;
    imageDecoding.memorySource = options.memorySource;
    reader.SetImageLoader(loadGltfImage, &imageDecoding);
    reader.SetFsCallbacks(
        {tinygltf::FileExists, tinygltf::ExpandFilePath, readRegularFile, tinygltf::WriteWholeFile, &files});
    tinygltf::Model model;
    std::string error, warning;
    // tinygltf reads the file's bytes, or the changed JSON (and a GLB's other chunks as they are), from
    // memory; external buffers and images relative to the file's folder.
    const std::string directory = std::filesystem::path(path).parent_path().string();
    const std::string changed = !rewritten ? std::string()
                                : binary   ? replaceGlbJson(file, document.dump(), path)
                                           : document.dump();
    // Only tinygltf's own parse of the JSON from here: the document, and the file where it was rewritten, are
    // let go first (three copies of a JSON of 100,000 nodes, each 13 to 14 times its text, took 0.8 GB).
    nlohmann::json().swap(document);
    if (rewritten) std::string().swap(file);
    const std::string& bytes = rewritten ? changed : file;
    const bool ok = binary ? reader.LoadBinaryFromMemory(&model, &error, &warning,
                                                         reinterpret_cast<const unsigned char*>(bytes.data()),
                                                         static_cast<unsigned int>(bytes.size()), directory)
                           : reader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                                        static_cast<unsigned int>(bytes.size()), directory);
    if (!ok || !error.empty()) {
        std::string message = error.empty() ? "not a valid glTF file" : error;
        // tinygltf's messages can span lines; the command line reports one, of a readable length (a data URI
        // it could not decode was quoted whole: an error line of 4 MB).
        std::replace(message.begin(), message.end(), '\n', ' ');
        while (!message.empty() && message.back() == ' ') message.pop_back();
        constexpr size_t kLongestMessage = 400;
        if (message.size() > kLongestMessage) message = message.substr(0, kLongestMessage) + "...";
        throw SceneError(path + ": " + message);
    }
    return model;
}

}  // namespace

Scene loadGltf(const std::string& path, const LoadOptions& options) {
    try {
        ImageDecoding imageDecoding;
        std::vector<std::string> files;
        std::optional<std::set<int>> placed;
        tinygltf::Model model = parseGltf(path, options, imageDecoding, files, placed);
        decompressMeshes(model, path,
                         options.maxSceneBytes - std::min(options.maxSceneBytes, imageDecoding.decodedBytes),
                         options.memorySource);
        GltfConverter converter(model, path, options, std::move(imageDecoding.failures),
                                imageDecoding.decodedBytes, std::move(placed));
        Scene scene = converter.convert();
        scene.files = std::move(files);
        return scene;
    } catch (const std::bad_alloc&) {
        // An allocation the loader's estimates did not foresee (a library's, sized by the file): the file
        // asked for more memory than there is.
        throw SceneError(path + ": the host ran out of memory while loading the file");
    }
}

}  // namespace vkrt
