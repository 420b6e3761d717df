#include "scene/gltf_loader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <tiny_gltf.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/gltf_accessors.h"
#include "scene/gltf_animation.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

constexpr std::array<const char*, 7> kSupportedExtensions = {"KHR_materials_emissive_strength",
                                                             "KHR_materials_transmission",
                                                             "KHR_materials_ior",
                                                             "KHR_materials_volume",
                                                             "KHR_lights_punctual",
                                                             "EXT_mesh_gpu_instancing",
                                                             "VKRT_sphere"};

// Everything the node walk needs, so that helpers stay small.
class GltfConverter {
  public:
    GltfConverter(const tinygltf::Model& model, std::string path, const LoadOptions& options)
        : model_(model),
          path_(std::move(path)),
          options_(options),
          accessors_(model_, path_),
          animations_(model_, accessors_, path_) {}

    Scene convert();

  private:
    // A node's world transform at the shutter's opening and at the end of each motion segment.
    using Poses = std::vector<glm::dmat4>;

    [[noreturn]] void fail(const std::string& message) const { throw SceneError(path_ + ": " + message); }
    void warn(const std::string& message) { scene_.warnings.push_back(message); }

    void checkExtensions();
    void convertTextures();
    void convertMaterials();
    double number(const tinygltf::Value& object, const char* key, double fallback,
                  const std::string& where) const;
    glm::vec3 vector3(const tinygltf::Value& object, const char* key, glm::vec3 fallback,
                      const std::string& where) const;
    int textureIndex(int gltfTexture, const std::string& where) const;

    std::vector<int> sceneRoots() const;
    glm::dvec3 approximateCenter(const std::vector<int>& roots) const;
    void checkNodeGraph(const std::vector<int>& roots) const;
    glm::dmat4 localTransform(int nodeIndex) const;
    glm::dmat4 localTransformAt(int nodeIndex, double time) const;
    void chooseShutter();
    void walk(int nodeIndex, const Poses& parents);
    void addMesh(int meshIndex, const Poses& poses);
    std::vector<glm::dmat4> instanceTransforms(const tinygltf::Value& extension,
                                               const std::string& where) const;
    void addPrimitive(const tinygltf::Primitive& primitive, const std::string& where, const Poses& poses);
    void addCamera(int cameraIndex, const glm::dmat4& world, const std::string& nodeName);
    void addLight(const tinygltf::Value& extension, const glm::dmat4& world, const std::string& where);
    Sphere placeSphere(const tinygltf::Value& extension, const glm::dmat4& world, const std::string& where);
    uint32_t defaultMaterial();

    const tinygltf::Model& model_;
    std::string path_;
    LoadOptions options_;
    AccessorReader accessors_;
    NodeAnimations animations_;
    std::vector<double> poseTimes_;  // the shutter's opening, then the end of each motion segment
    Scene scene_;
    int defaultMaterial_ = -1;
    size_t degenerateTriangles_ = 0;
    std::set<int> skippedModes_;
};

std::string describe(const char* kind, int index, const std::string& name) {
    std::string s = std::string(kind) + " " + std::to_string(index);
    if (!name.empty()) s += " ('" + name + "')";
    return s;
}

bool allFinite(const std::vector<double>& values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

Scene GltfConverter::convert() {
    scene_.sourcePath = path_;
    checkExtensions();
    convertTextures();
    convertMaterials();

    std::vector<int> roots = sceneRoots();
    checkNodeGraph(roots);
    // Walk with the scene's approximate centre moved to the origin (re-centring keeps float precision).
    scene_.origin = approximateCenter(roots);
    const glm::dmat4 recentre = glm::translate(glm::dmat4(1.0), -scene_.origin);
    chooseShutter();
    for (int root : roots) walk(root, Poses(poseTimes_.size(), recentre));

    if (degenerateTriangles_ > 0) {
        warn(std::to_string(degenerateTriangles_) + " degenerate (zero-area) triangle(s) skipped");
    }
    for (int mode : skippedModes_) {
        warn("primitives with mode " + std::to_string(mode) +
             " (points or lines) skipped: vkrt renders triangles");
    }
    if (scene_.triangles.empty() && scene_.spheres.empty()) warn("the scene has no triangles or spheres");

    finalizeScene(scene_);
    return std::move(scene_);
}

void GltfConverter::checkExtensions() {
    for (const std::string& name : model_.extensionsRequired) {
        if (!isSupportedExtension(name)) fail("requires extension " + name + ", which vkrt does not support");
    }
    for (const std::string& name : model_.extensionsUsed) {
        if (!isSupportedExtension(name)) warn("ignoring optional extension " + name);
    }
}

void GltfConverter::convertTextures() {
    for (size_t i = 0; i < model_.textures.size(); ++i) {
        const tinygltf::Texture& gltfTexture = model_.textures[i];
        Texture texture;
        texture.name = gltfTexture.name;
        if (gltfTexture.source < 0 || gltfTexture.source >= static_cast<int>(model_.images.size())) {
            // Textures without a core image source (e.g. only KHR_texture_basisu) stay empty; using one
            // fails.
            scene_.textures.push_back(texture);
            continue;
        }
        const tinygltf::Image& image = model_.images[gltfTexture.source];
        if (!image.image.empty() && image.width > 0 && image.height > 0 && image.component >= 1 &&
            image.component <= 4 && (image.bits == 8 || image.bits == 16)) {
            texture.width = image.width;
            texture.height = image.height;
            const size_t pixels = static_cast<size_t>(image.width) * image.height;
            const size_t bytesPerChannel = image.bits / 8;
            if (image.image.size() < pixels * image.component * bytesPerChannel) {
                fail(describe("image", gltfTexture.source, image.uri) + " has fewer pixels than its size");
            }
            texture.rgba.resize(pixels * 4);
            for (size_t p = 0; p < pixels; ++p) {
                uint8_t channel[4] = {0, 0, 0, 255};
                for (int c = 0; c < image.component; ++c) {
                    // 16-bit images keep their high byte (little-endian storage, as tinygltf decodes).
                    size_t at = (p * image.component + c) * bytesPerChannel + (bytesPerChannel - 1);
                    channel[c] = image.image[at];
                }
                if (image.component <= 2) {  // grey or grey + alpha
                    channel[3] = image.component == 2 ? channel[1] : 255;
                    channel[1] = channel[2] = channel[0];
                }
                std::copy(channel, channel + 4, texture.rgba.begin() + p * 4);
            }
        }
        if (gltfTexture.sampler >= 0) {
            if (gltfTexture.sampler >= static_cast<int>(model_.samplers.size())) {
                fail(describe("texture", static_cast<int>(i), gltfTexture.name) + " refers to sampler " +
                     std::to_string(gltfTexture.sampler) + ", which does not exist");
            }
            const tinygltf::Sampler& sampler = model_.samplers[gltfTexture.sampler];
            auto wrap = [](int mode) {
                if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::ClampToEdge;
                if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::MirroredRepeat;
                return WrapMode::Repeat;
            };
            texture.wrapS = wrap(sampler.wrapS);
            texture.wrapT = wrap(sampler.wrapT);
            texture.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        scene_.textures.push_back(std::move(texture));
    }
}

double GltfConverter::number(const tinygltf::Value& object, const char* key, double fallback,
                             const std::string& where) const {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    if (!value.IsNumber()) fail(where + ": '" + key + "' must be a number");
    double v = value.GetNumberAsDouble();
    if (!std::isfinite(v)) fail(where + ": '" + key + "' is not finite");
    return v;
}

glm::vec3 GltfConverter::vector3(const tinygltf::Value& object, const char* key, glm::vec3 fallback,
                                 const std::string& where) const {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    if (!value.IsArray() || value.ArrayLen() != 3)
        fail(where + ": '" + key + "' must be an array of 3 numbers");
    glm::vec3 v;
    for (int c = 0; c < 3; ++c) {
        if (!value.Get(c).IsNumber()) fail(where + ": '" + key + "' must be an array of 3 numbers");
        v[c] = static_cast<float>(value.Get(c).GetNumberAsDouble());
    }
    return v;
}

int GltfConverter::textureIndex(int gltfTexture, const std::string& where) const {
    if (gltfTexture < 0) return -1;
    if (gltfTexture >= static_cast<int>(scene_.textures.size())) {
        fail(where + " refers to texture " + std::to_string(gltfTexture) + ", which does not exist");
    }
    const tinygltf::Texture& texture = model_.textures[gltfTexture];
    if (scene_.textures[gltfTexture].rgba.empty()) {
        std::string image = "its image";
        if (texture.source >= 0 && texture.source < static_cast<int>(model_.images.size())) {
            const tinygltf::Image& img = model_.images[texture.source];
            image = describe("image", texture.source, img.uri.empty() ? img.name : img.uri);
        }
        fail(where + " uses texture " + std::to_string(gltfTexture) + " but " + image +
             " is missing or could not be decoded");
    }
    return gltfTexture;
}

void GltfConverter::convertMaterials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
        const tinygltf::Material& m = model_.materials[i];
        const std::string where = describe("material", static_cast<int>(i), m.name);
        Material material;
        material.name = m.name;
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() != 4 || !allFinite(pbr.baseColorFactor)) {
            fail(where + ": baseColorFactor must be 4 finite numbers");
        }
        material.baseColor = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                                       pbr.baseColorFactor[3]);
        material.baseColorTexture = textureIndex(pbr.baseColorTexture.index, where);
        if (pbr.baseColorTexture.texCoord != 0)
            warn(where + ": base colour texture uses TEXCOORD_" +
                 std::to_string(pbr.baseColorTexture.texCoord) + "; vkrt reads TEXCOORD_0");
        material.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
        material.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
        if (m.emissiveFactor.size() != 3 || !allFinite(m.emissiveFactor)) {
            fail(where + ": emissiveFactor must be 3 finite numbers");
        }
        glm::vec3 emissive(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
        material.doubleSided = m.doubleSided;

        float strength = 1.0f;
        for (const auto& [name, value] : m.extensions) {
            const std::string extWhere = where + " " + name;
            if (!value.IsObject()) fail(extWhere + " must be a JSON object");
            if (name == "KHR_materials_emissive_strength") {
                strength = static_cast<float>(number(value, "emissiveStrength", 1.0, extWhere));
            } else if (name == "KHR_materials_transmission") {
                material.transmission = static_cast<float>(
                    std::clamp(number(value, "transmissionFactor", 0.0, extWhere), 0.0, 1.0));
            } else if (name == "KHR_materials_ior") {
                material.ior = static_cast<float>(number(value, "ior", 1.5, extWhere));
                if (material.ior != 0.0f && material.ior < 1.0f)
                    fail(extWhere + ": ior must be 0 or at least 1");
            } else if (name == "KHR_materials_volume") {
                material.thickness =
                    static_cast<float>(std::max(0.0, number(value, "thicknessFactor", 0.0, extWhere)));
                material.attenuationDistance = static_cast<float>(
                    number(value, "attenuationDistance", std::numeric_limits<double>::infinity(), extWhere));
                if (!(material.attenuationDistance > 0.0f))
                    fail(extWhere + ": attenuationDistance must be positive");
                material.attenuationColor = vector3(value, "attenuationColor", glm::vec3(1.0f), extWhere);
            }
        }
        // KHR_materials_ior: ior 0 stands for infinity, i.e. a perfect mirror; 1e6 is close enough.
        if (material.ior == 0.0f) material.ior = 1e6f;
        if (strength < 0.0f) fail(where + ": emissiveStrength must not be negative");
        material.emission = glm::max(emissive, glm::vec3(0.0f)) * strength;
        material.emissiveTexture = textureIndex(m.emissiveTexture.index, where);
        scene_.materials.push_back(material);
    }
}

uint32_t GltfConverter::defaultMaterial() {
    if (defaultMaterial_ < 0) {
        defaultMaterial_ = static_cast<int>(scene_.materials.size());
        Material material;  // glTF's default material: white, metallic 1, roughness 1
        material.name = "default";
        scene_.materials.push_back(material);
    }
    return static_cast<uint32_t>(defaultMaterial_);
}

std::vector<int> GltfConverter::sceneRoots() const {
    if (!model_.scenes.empty()) {
        int index = model_.defaultScene >= 0 ? model_.defaultScene : 0;
        if (index >= static_cast<int>(model_.scenes.size())) {
            fail("default scene " + std::to_string(index) + " does not exist");
        }
        return model_.scenes[index].nodes;
    }
    // No scene: render every node that is nobody's child.
    std::vector<bool> isChild(model_.nodes.size(), false);
    for (const tinygltf::Node& node : model_.nodes) {
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

// The centre of the bounds that the POSITION accessors' min and max give, placed by the node transforms
// (instancing ignored); the origin when no accessor has bounds.
glm::dvec3 GltfConverter::approximateCenter(const std::vector<int>& roots) const {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    std::function<void(int, const glm::dmat4&)> visit = [&](int nodeIndex, const glm::dmat4& parent) {
        const tinygltf::Node& node = model_.nodes[nodeIndex];
        const glm::dmat4 world = parent * localTransform(nodeIndex);
        if (node.mesh >= 0 && node.mesh < static_cast<int>(model_.meshes.size())) {
            for (const tinygltf::Primitive& primitive : model_.meshes[node.mesh].primitives) {
                auto position = primitive.attributes.find("POSITION");
                if (position == primitive.attributes.end() || position->second < 0 ||
                    position->second >= static_cast<int>(model_.accessors.size())) {
                    continue;
                }
                const tinygltf::Accessor& accessor = model_.accessors[position->second];
                if (accessor.minValues.size() != 3 || accessor.maxValues.size() != 3) continue;
                for (int corner = 0; corner < 8; ++corner) {
                    const glm::dvec4 p(corner & 1 ? accessor.maxValues[0] : accessor.minValues[0],
                                       corner & 2 ? accessor.maxValues[1] : accessor.minValues[1],
                                       corner & 4 ? accessor.maxValues[2] : accessor.minValues[2], 1.0);
                    const glm::dvec3 q(world * p);
                    if (!std::isfinite(q.x + q.y + q.z)) continue;
                    lo = glm::min(lo, q);
                    hi = glm::max(hi, q);
                }
            }
        }
        auto sphere = node.extensions.find("VKRT_sphere");
        if (sphere != node.extensions.end()) {
            const glm::dvec3 q(world[3]);
            if (std::isfinite(q.x + q.y + q.z)) {
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
            }
        }
        for (int child : node.children) visit(child, world);
    };
    for (int root : roots) visit(root, glm::dmat4(1.0));
    return lo.x <= hi.x ? 0.5 * (lo + hi) : glm::dvec3(0.0);
}

// The node graph must be a forest: indices in range, no cycles, no node with two parents.
void GltfConverter::checkNodeGraph(const std::vector<int>& roots) const {
    const int nodeCount = static_cast<int>(model_.nodes.size());
    std::vector<int> parent(nodeCount, -1);
    for (int i = 0; i < nodeCount; ++i) {
        for (int child : model_.nodes[i].children) {
            if (child < 0 || child >= nodeCount) {
                fail(describe("node", i, model_.nodes[i].name) + " has child " + std::to_string(child) +
                     ", which does not exist");
            }
            if (child == i) fail(describe("node", i, model_.nodes[i].name) + " is its own child (a cycle)");
            if (parent[child] >= 0) {
                fail(describe("node", child, model_.nodes[child].name) + " has two parents, nodes " +
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
            fail("the node graph has a cycle through " + describe("node", n, model_.nodes[n].name));
        }
        for (int c : chain) state[c] = 2;
    }
    for (int root : roots) {
        if (root < 0 || root >= nodeCount)
            fail("the scene refers to node " + std::to_string(root) + ", which does not exist");
        if (parent[root] >= 0)
            fail(describe("node", root, model_.nodes[root].name) + " is a scene root and a child");
    }
}

glm::dmat4 GltfConverter::localTransform(int nodeIndex) const {
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    const std::string where = describe("node", nodeIndex, node.name);
    auto check = [&](const std::vector<double>& v, size_t n, const char* what) {
        if (!v.empty() && v.size() != n)
            fail(where + ": " + what + " must have " + std::to_string(n) + " numbers");
        if (!allFinite(v)) fail(where + ": " + what + " is not finite");
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
    glm::dmat4 m(1.0);
    if (!node.translation.empty()) {
        m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (!node.rotation.empty()) {
        // glTF stores quaternions as (x, y, z, w); GLM's constructor takes (w, x, y, z).
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        double len = glm::length(q);
        if (!(len > 0.0)) fail(where + ": rotation quaternion has zero length");
        m = m * glm::mat4_cast(q / len);
    }
    if (!node.scale.empty()) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

// The shutter interval: the caller's, else the scene's extras {"shutter": [open, close]} (seconds of the
// file's animation timeline), else closed at 0.
void GltfConverter::chooseShutter() {
    if (options_.shutter) {
        scene_.shutterOpen = (*options_.shutter)[0];
        scene_.shutterClose = (*options_.shutter)[1];
    } else if (!model_.scenes.empty()) {
        const tinygltf::Value& extras = model_.scenes[std::max(0, model_.defaultScene)].extras;
        if (extras.IsObject() && extras.Has("shutter")) {
            const tinygltf::Value& shutter = extras.Get("shutter");
            if (!shutter.IsArray() || shutter.ArrayLen() != 2 || !shutter.Get(0).IsNumber() ||
                !shutter.Get(1).IsNumber()) {
                fail("the scene's extras.shutter must be [open, close]");
            }
            scene_.shutterOpen = shutter.Get(0).GetNumberAsDouble();
            scene_.shutterClose = shutter.Get(1).GetNumberAsDouble();
        }
    }
    if (!std::isfinite(scene_.shutterOpen) || !std::isfinite(scene_.shutterClose) ||
        scene_.shutterClose < scene_.shutterOpen) {
        fail("the shutter must close at or after it opens");
    }
    // Motion segments: one when everything moves by linear translation alone (exact), else
    // kMotionSegments, whose poses follow rotations, curves and steps within the shutter.
    poseTimes_ = {scene_.shutterOpen};
    if (scene_.shutterClose > scene_.shutterOpen && !animations_.empty()) {
        scene_.motionSegments =
            animations_.linearTranslationOnly(scene_.shutterOpen, scene_.shutterClose) ? 1 : kMotionSegments;
        for (int k = 1; k <= scene_.motionSegments; ++k) {
            poseTimes_.push_back(scene_.shutterOpen +
                                 (scene_.shutterClose - scene_.shutterOpen) * k / scene_.motionSegments);
        }
    }
}

glm::dmat4 GltfConverter::localTransformAt(int nodeIndex, double time) const {
    if (!animations_.animates(nodeIndex)) return localTransform(nodeIndex);
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    localTransform(nodeIndex);  // validates the static values
    NodeTrs rest;
    if (!node.translation.empty())
        rest.translation = {node.translation[0], node.translation[1], node.translation[2]};
    if (!node.rotation.empty()) {
        rest.rotation = glm::normalize(
            glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    }
    if (!node.scale.empty()) rest.scale = {node.scale[0], node.scale[1], node.scale[2]};
    return animations_.evaluate(nodeIndex, rest, time).matrix();
}

void GltfConverter::walk(int nodeIndex, const Poses& parents) {
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    Poses poses(parents.size());
    for (size_t k = 0; k < poses.size(); ++k)
        poses[k] = parents[k] * localTransformAt(nodeIndex, poseTimes_[k]);
    const glm::dmat4& world = poses[0];
    const std::string where = describe("node", nodeIndex, node.name);
    if (node.mesh >= 0) {
        if (node.mesh >= static_cast<int>(model_.meshes.size())) {
            fail(where + " refers to mesh " + std::to_string(node.mesh) + ", which does not exist");
        }
        auto instancing = node.extensions.find("EXT_mesh_gpu_instancing");
        if (instancing == node.extensions.end()) {
            addMesh(node.mesh, poses);
        } else {
            for (const glm::dmat4& instance : instanceTransforms(instancing->second, where)) {
                Poses instancePoses = poses;
                for (glm::dmat4& pose : instancePoses) pose = pose * instance;
                addMesh(node.mesh, instancePoses);
            }
        }
    }
    if (node.camera >= 0) addCamera(node.camera, world, node.name);
    auto light = node.extensions.find("KHR_lights_punctual");
    if (light != node.extensions.end()) addLight(light->second, world, where);
    auto sphere = node.extensions.find("VKRT_sphere");
    if (sphere != node.extensions.end()) {
        scene_.spheres.push_back(placeSphere(sphere->second, world, where));
        for (size_t k = 1; k < poses.size(); ++k)
            scene_.spherePoses.push_back(placeSphere(sphere->second, poses[k], where));
    }
    for (int child : node.children) walk(child, poses);
}

// EXT_mesh_gpu_instancing: one translation / rotation / scale per instance, applied before the node's own
// transform (instance transforms are in the node's local space).
std::vector<glm::dmat4> GltfConverter::instanceTransforms(const tinygltf::Value& extension,
                                                          const std::string& where) const {
    const std::string extWhere = where + " EXT_mesh_gpu_instancing";
    if (!extension.IsObject() || !extension.Has("attributes") || !extension.Get("attributes").IsObject()) {
        fail(extWhere + " needs an 'attributes' object");
    }
    const tinygltf::Value& attributes = extension.Get("attributes");
    std::vector<float> translation, rotation, scale;
    size_t count = 0;
    bool any = false;
    auto read = [&](const char* name, int components, std::vector<float>& out) {
        if (!attributes.Has(name)) return;
        if (!attributes.Get(name).IsInt())
            fail(extWhere + ": attribute " + name + " must be an accessor index");
        out = accessors_.readFloats(attributes.Get(name).GetNumberAsInt(), components, extWhere + " " + name);
        const size_t n = out.size() / components;
        if (any && n != count) fail(extWhere + ": attributes have different counts");
        count = n;
        any = true;
        for (float v : out) {
            if (!std::isfinite(v)) fail(extWhere + " " + name + " has a non-finite value");
        }
    };
    read("TRANSLATION", 3, translation);
    read("ROTATION", 4, rotation);
    read("SCALE", 3, scale);
    if (!any) fail(extWhere + " has no TRANSLATION, ROTATION or SCALE attribute");
    std::vector<glm::dmat4> transforms(count, glm::dmat4(1.0));
    for (size_t i = 0; i < count; ++i) {
        glm::dmat4& m = transforms[i];
        if (!translation.empty())
            m = glm::translate(
                m, glm::dvec3(translation[3 * i], translation[3 * i + 1], translation[3 * i + 2]));
        if (!rotation.empty()) {
            glm::dquat q(rotation[4 * i + 3], rotation[4 * i], rotation[4 * i + 1], rotation[4 * i + 2]);
            const double length = glm::length(q);
            if (!(length > 0.0))
                fail(extWhere + ": instance " + std::to_string(i) + " has a zero rotation quaternion");
            m = m * glm::mat4_cast(q / length);
        }
        if (!scale.empty()) m = glm::scale(m, glm::dvec3(scale[3 * i], scale[3 * i + 1], scale[3 * i + 2]));
    }
    return transforms;
}

void GltfConverter::addMesh(int meshIndex, const Poses& poses) {
    const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        addPrimitive(mesh.primitives[p],
                     describe("mesh", meshIndex, mesh.name) + " primitive " + std::to_string(p), poses);
    }
}

void GltfConverter::addPrimitive(const tinygltf::Primitive& primitive, const std::string& where,
                                 const Poses& poses) {
    const glm::dmat4& world = poses[0];
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= 3) {
        skippedModes_.insert(mode);
        return;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        fail(where + " has an invalid mode " + std::to_string(mode));
    }
    auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) fail(where + " has no POSITION attribute");
    const std::vector<float> positions = accessors_.readFloats(position->second, 3, where + " POSITION");
    const size_t vertexCount = positions.size() / 3;
    for (size_t i = 0; i < positions.size(); ++i) {
        if (!std::isfinite(positions[i])) {
            fail(where + " POSITION has a non-finite value at vertex " + std::to_string(i / 3));
        }
    }
    std::vector<float> normals, uvs;
    if (auto it = primitive.attributes.find("NORMAL"); it != primitive.attributes.end()) {
        normals = accessors_.readFloats(it->second, 3, where + " NORMAL");
        if (normals.size() != positions.size()) fail(where + " NORMAL and POSITION counts differ");
    }
    if (auto it = primitive.attributes.find("TEXCOORD_0"); it != primitive.attributes.end()) {
        uvs = accessors_.readFloats(it->second, 2, where + " TEXCOORD_0");
        if (uvs.size() / 2 != vertexCount) fail(where + " TEXCOORD_0 and POSITION counts differ");
    }

    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
        indices = accessors_.readIndices(primitive.indices, where + " indices");
        for (size_t i = 0; i < indices.size(); ++i) {
            if (indices[i] >= vertexCount) {
                fail(where + " index " + std::to_string(indices[i]) + " at position " + std::to_string(i) +
                     " is out of range (the primitive has " + std::to_string(vertexCount) + " vertices)");
            }
        }
    } else {
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
    }

    // Triangle list from strips and fans (glTF 2.0 section 3.7.2.1).
    std::vector<std::array<uint32_t, 3>> faces;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < indices.size(); i += 3)
            faces.push_back({indices[i], indices[i + 1], indices[i + 2]});
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < indices.size(); ++i) {
            if (i % 2 == 0)
                faces.push_back({indices[i], indices[i + 1], indices[i + 2]});
            else
                faces.push_back({indices[i], indices[i + 2], indices[i + 1]});
        }
    } else {
        for (size_t i = 0; i + 2 < indices.size(); ++i)
            faces.push_back({indices[i + 1], indices[i + 2], indices[0]});
    }

    uint32_t material;
    if (primitive.material < 0) {
        material = defaultMaterial();
    } else if (primitive.material >= static_cast<int>(model_.materials.size())) {
        fail(where + " refers to material " + std::to_string(primitive.material) + ", which does not exist");
    } else {
        material = static_cast<uint32_t>(primitive.material);
    }

    const glm::dmat3 linear(world);
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) < 0.0;  // mirroring reverses the winding
    auto placed = [&](const glm::dmat4& transform, uint32_t v) {
        return glm::vec3(transform *
                         glm::dvec4(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 1.0));
    };
    auto worldPosition = [&](uint32_t v) { return placed(world, v); };
    for (auto face : faces) {
        if (mirrored) std::swap(face[1], face[2]);
        Triangle triangle{worldPosition(face[0]), worldPosition(face[1]), worldPosition(face[2]), material};
        if (!std::isfinite(triangle.v0.x + triangle.v0.y + triangle.v0.z + triangle.v1.x + triangle.v1.y +
                           triangle.v1.z + triangle.v2.x + triangle.v2.y + triangle.v2.z)) {
            fail(where + " has a vertex that its node transform moves out of floating-point range");
        }
        const glm::dvec3 cross = glm::cross(glm::dvec3(triangle.v1) - glm::dvec3(triangle.v0),
                                            glm::dvec3(triangle.v2) - glm::dvec3(triangle.v0));
        const double crossLength = glm::length(cross);
        if (!(crossLength > 0.0)) {
            ++degenerateTriangles_;
            continue;
        }
        const glm::vec3 geometric(cross / crossLength);
        TriangleShading shading{};
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = face[k];
            shading.normal[k] = geometric;
            if (!normals.empty()) {
                glm::dvec3 n =
                    normalMatrix * glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
                double length = glm::length(n);
                if (length > 0.0 && std::isfinite(length)) shading.normal[k] = glm::vec3(n / length);
            }
            if (!uvs.empty()) shading.uv[k] = glm::vec2(uvs[2 * v], uvs[2 * v + 1]);
        }
        scene_.triangles.push_back(triangle);
        scene_.shading.push_back(shading);
        for (size_t k = 1; k < poses.size(); ++k) {
            const Triangle pose{placed(poses[k], face[0]), placed(poses[k], face[1]),
                                placed(poses[k], face[2]), material};
            if (!std::isfinite(pose.v0.x + pose.v0.y + pose.v0.z + pose.v1.x + pose.v1.y + pose.v1.z +
                               pose.v2.x + pose.v2.y + pose.v2.z)) {
                fail(where + " has a vertex that its animation moves out of floating-point range");
            }
            scene_.trianglePoses.push_back(pose);
        }
    }
}

void GltfConverter::addCamera(int cameraIndex, const glm::dmat4& world, const std::string& nodeName) {
    if (cameraIndex >= static_cast<int>(model_.cameras.size())) {
        fail("node '" + nodeName + "' refers to camera " + std::to_string(cameraIndex) +
             ", which does not exist");
    }
    const tinygltf::Camera& source = model_.cameras[cameraIndex];
    const std::string where = describe("camera", cameraIndex, source.name);
    Camera camera;
    camera.name = source.name.empty() ? (nodeName.empty() ? where : nodeName) : source.name;
    if (source.type == "perspective") {
        camera.projection = Projection::Perspective;
        camera.yfov = source.perspective.yfov;
        camera.aspectRatio = source.perspective.aspectRatio;
        if (!(camera.yfov > 0.0 && camera.yfov < M_PI)) fail(where + ": yfov must be in (0, pi)");
    } else if (source.type == "orthographic") {
        camera.projection = Projection::Orthographic;
        camera.xmag = source.orthographic.xmag;
        camera.ymag = source.orthographic.ymag;
        if (!(camera.xmag != 0.0 && camera.ymag != 0.0 && std::isfinite(camera.xmag) &&
              std::isfinite(camera.ymag))) {
            fail(where + ": xmag and ymag must be finite and non-zero");
        }
    } else {
        fail(where + " has unknown type '" + source.type + "'");
    }
    // Depth of field from the camera's extras (vkrt's convention): {"aperture": lens radius, "focusDistance":
    // d}.
    camera.aperture = number(source.extras, "aperture", 0.0, where + " extras");
    camera.focusDistance = number(source.extras, "focusDistance", 0.0, where + " extras");
    if (camera.aperture < 0.0 || camera.focusDistance < 0.0)
        fail(where + ": aperture and focusDistance must be >= 0");
    // glTF cameras look down the node's -Z with +Y up; scale in the node is ignored (section 3.10.1).
    const glm::dmat3 linear(world);
    camera.position = glm::dvec3(world[3]);
    camera.forward = glm::normalize(linear * glm::dvec3(0.0, 0.0, -1.0));
    glm::dvec3 up = linear * glm::dvec3(0.0, 1.0, 0.0);
    camera.right = glm::normalize(glm::cross(camera.forward, up));
    camera.up = glm::cross(camera.right, camera.forward);
    if (!std::isfinite(camera.right.x + camera.right.y + camera.right.z))
        fail(where + ": its node transform is singular");
    scene_.cameras.push_back(camera);
}

void GltfConverter::addLight(const tinygltf::Value& extension, const glm::dmat4& world,
                             const std::string& where) {
    if (!extension.IsObject() || !extension.Has("light") || !extension.Get("light").IsInt()) {
        fail(where + ": KHR_lights_punctual must name a light by index");
    }
    const int index = extension.Get("light").GetNumberAsInt();
    if (index < 0 || index >= static_cast<int>(model_.lights.size())) {
        fail(where + " refers to light " + std::to_string(index) + ", which does not exist");
    }
    const tinygltf::Light& source = model_.lights[index];
    const std::string lightWhere = describe("light", index, source.name);
    PunctualLight light;
    light.name = source.name;
    if (source.type == "point")
        light.type = LightType::Point;
    else if (source.type == "spot")
        light.type = LightType::Spot;
    else if (source.type == "directional")
        light.type = LightType::Directional;
    else
        fail(lightWhere + " has unknown type '" + source.type + "'");
    if (!source.color.empty()) {
        if (source.color.size() != 3 || !allFinite(source.color))
            fail(lightWhere + ": color must be 3 numbers");
        light.color = glm::vec3(source.color[0], source.color[1], source.color[2]);
    }
    if (!std::isfinite(source.intensity) || source.intensity < 0.0)
        fail(lightWhere + ": intensity must be >= 0");
    light.intensity = static_cast<float>(source.intensity);
    light.range = static_cast<float>(std::max(0.0, source.range));
    light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
    light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
    if (light.type == LightType::Spot &&
        !(light.innerConeAngle >= 0.0f && light.innerConeAngle < light.outerConeAngle &&
          light.outerConeAngle <= static_cast<float>(M_PI / 2))) {
        fail(lightWhere + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
    }
    light.position = glm::dvec3(world[3]);
    light.direction = glm::normalize(glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0));
    scene_.lights.push_back(light);
}

// VKRT_sphere (docs/vkrt_sphere.md): a sphere of `radius` around the node's origin, placed by the node's
// transform, which must scale uniformly.
Sphere GltfConverter::placeSphere(const tinygltf::Value& extension, const glm::dmat4& world,
                                  const std::string& where) {
    const std::string sphereWhere = where + " VKRT_sphere";
    if (!extension.IsObject()) fail(sphereWhere + " must be an object");
    const double radius = number(extension, "radius", -1.0, sphereWhere);
    if (!(radius > 0.0) || !std::isfinite(radius)) fail(sphereWhere + ": radius must be a finite number > 0");
    uint32_t material = 0;
    if (!extension.Has("material")) {
        material = defaultMaterial();
    } else {
        const tinygltf::Value& value = extension.Get("material");
        if (!value.IsInt() || value.GetNumberAsInt() < 0 ||
            value.GetNumberAsInt() >= static_cast<int>(model_.materials.size())) {
            fail(sphereWhere + ": material must be the index of a material");
        }
        material = static_cast<uint32_t>(value.GetNumberAsInt());
    }
    const glm::dmat3 linear(world);
    const double sx = glm::length(linear[0]), sy = glm::length(linear[1]), sz = glm::length(linear[2]);
    const double scale = (sx + sy + sz) / 3.0;
    if (!(scale > 0.0) || std::abs(sx - scale) > 1e-4 * scale || std::abs(sy - scale) > 1e-4 * scale ||
        std::abs(sz - scale) > 1e-4 * scale) {
        fail(sphereWhere + ": the node transform must scale uniformly (a sphere stays a sphere)");
    }
    const glm::dvec3 center(world[3]);
    const double worldRadius = radius * scale;
    if (!std::isfinite(center.x + center.y + center.z) || !(worldRadius < 1e30)) {
        fail(sphereWhere + ": the placed sphere is not finite");
    }
    return {glm::vec3(center), static_cast<float>(worldRadius), material};
}

bool hasGlbMagic(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    char magic[4] = {};
    file.read(magic, 4);
    return file.gcount() == 4 && std::string(magic, 4) == "glTF";
}

}  // namespace

bool isSupportedExtension(const std::string& name) {
    return std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), name) !=
           kSupportedExtensions.end();
}

Scene loadGltf(const std::string& path, const LoadOptions& options) {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw SceneError(path + ": cannot open file");
    probe.close();

    tinygltf::TinyGLTF reader;
    tinygltf::Model model;
    std::string error, warning;
    const bool binary = hasGlbMagic(path);
    const bool ok = binary ? reader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : reader.LoadASCIIFromFile(&model, &error, &warning, path);
    if (!ok || !error.empty()) {
        std::string message = error.empty() ? "not a valid glTF file" : error;
        // tinygltf's messages can span lines; the command line reports one.
        std::replace(message.begin(), message.end(), '\n', ' ');
        while (!message.empty() && message.back() == ' ') message.pop_back();
        throw SceneError(path + ": " + message);
    }
    GltfConverter converter(model, path, options);
    return converter.convert();
}

}  // namespace vkrt
