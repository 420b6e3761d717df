#include "scene/gltf_loader.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
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
#include "scene/gltf_transforms.h"
#include "scene/scene_builder.h"

namespace vkrt {
namespace {

// The conversion of one model: materials first, then a walk of the node graph that places meshes,
// cameras, lights and spheres in the world.
class GltfConverter {
  public:
    GltfConverter(const tinygltf::Model& model, std::string path, const LoadOptions& options)
        : context_(model, std::move(path)),
          options_(options),
          animations_(model, context_.accessors, context_.path),
          meshes_(context_) {}

    Scene convert();

  private:
    // A node's world transform at the shutter's opening and at the end of each motion segment.
    using Poses = std::vector<glm::dmat4>;

    void chooseShutter();
    // Places the tree under `root` in the world, below `parents`.
    void walk(int root, const Poses& parents);
    // Places one node's mesh, camera, light, sphere and solid; returns its poses, its children's parents.
    Poses place(int nodeIndex, const Poses& parents);
    // Counts `instances` more placements of mesh `meshIndex` against the host memory the options allow,
    // before any of them is placed.
    void reserveTriangles(int meshIndex, uint64_t instances, const std::string& where);

    GltfContext context_;
    LoadOptions options_;
    NodeAnimations animations_;
    MeshInstancer meshes_;
    std::vector<double> poseTimes_;  // the shutter's opening, then the end of each motion segment
    uint64_t triangleBound_ = 0;     // the most triangles the meshes placed so far can have
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
    checkExtensions(context_);
    warnAboutUnsupportedFeatures(context_);
    convertTextures(context_);
    convertMaterials(context_);

    std::vector<int> roots = sceneRoots(context_);
    checkNodeGraph(context_, roots);
    // Walk with the scene's approximate centre moved to the origin (re-centring keeps float precision).
    scene.origin = approximateCenter(context_, roots);
    const glm::dmat4 recentre = glm::translate(glm::dmat4(1.0), -scene.origin);
    chooseShutter();
    for (int root : roots) walk(root, Poses(poseTimes_.size(), recentre));

    meshes_.warnAboutSkipped();
    if (scene.triangles.empty() && scene.spheres.empty() && scene.solids.empty())
        context_.warn("the scene has no triangles, spheres or shapes");

    finalizeScene(scene);
    return std::move(scene);
}

// The shutter interval: the caller's, else the scene's extras {"shutter": [open, close]} (seconds of the
// file's animation timeline), else closed at 0.
void GltfConverter::chooseShutter() {
    const tinygltf::Model& model = context_.model;
    Scene& scene = context_.scene;
    if (options_.shutter) {
        scene.shutterOpen = (*options_.shutter)[0];
        scene.shutterClose = (*options_.shutter)[1];
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

void GltfConverter::reserveTriangles(int meshIndex, uint64_t instances, const std::string& where) {
    // Each triangle keeps its corners and material at each pose, and its shading (normals, texture
    // coordinates).
    const uint64_t bytesPerTriangle = sizeof(Triangle) * poseTimes_.size() + sizeof(TriangleShading);
    const uint64_t limit = options_.maxSceneBytes / bytesPerTriangle;
    const uint64_t bound =
        triangleBound(context_.model, context_.model.meshes[static_cast<size_t>(meshIndex)]);
    if (bound > 0 && instances > (limit - std::min(limit, triangleBound_)) / bound) {
        const double total =
            static_cast<double>(triangleBound_) + static_cast<double>(bound) * static_cast<double>(instances);
        const double bytes = std::min(total * static_cast<double>(bytesPerTriangle), 1.8e19);
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
        if (instancing == node.extensions.end()) {
            reserveTriangles(node.mesh, 1, where);
            meshes_.addInstance(node.mesh, poses);
        } else {
            const std::vector<glm::dmat4> instances = instanceTransforms(context_, instancing->second, where);
            reserveTriangles(node.mesh, instances.size(), where);
            for (const glm::dmat4& instance : instances) {
                Poses instancePoses = poses;
                for (glm::dmat4& pose : instancePoses) pose = pose * instance;
                meshes_.addInstance(node.mesh, instancePoses);
            }
        }
    }
    // Place its camera, light and sphere.
    if (node.camera >= 0) addCamera(context_, node.camera, world, node.name);
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

bool hasGlbMagic(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    char magic[4] = {};
    file.read(magic, 4);
    return file.gcount() == 4 && std::string(magic, 4) == "glTF";
}

// tinygltf's file reading, refusing what is not a regular file: a buffer or image whose URI names a
// directory had it read the directory's size as a file's and ask for that much memory.
bool readRegularFile(std::vector<unsigned char>* out, std::string* error, const std::string& path,
                     void* user) {
    std::error_code status;
    if (!std::filesystem::is_regular_file(path, status)) {
        if (error) *error += "File is not a regular file: " + path + "\n";
        return false;
    }
    return tinygltf::ReadWholeFile(out, error, path, user);
}

// The GLB header's version (glTF 2.0, 4.4.2: version 2; version 1 was glTF 1.0's binary extension).
void checkGlbVersion(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    unsigned char header[8] = {};
    file.read(reinterpret_cast<char*>(header), 8);
    if (file.gcount() < 8) throw SceneError(path + ": not a valid GLB file (its header is cut short)");
    const uint32_t version =
        header[4] | header[5] << 8 | header[6] << 16 | static_cast<uint32_t>(header[7]) << 24;
    if (version != 2)
        throw SceneError(path + ": GLB version " + std::to_string(version) +
                         "; vkrt reads GLB version 2 (glTF 2.0)");
}

}  // namespace

Scene loadGltf(const std::string& path, const LoadOptions& options) {
    std::error_code statusError;
    if (std::filesystem::is_directory(path, statusError)) throw SceneError(path + ": is a directory");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw SceneError(path + ": cannot open file");
    probe.close();

    // The JSON first: a required extension vkrt lacks, then every property vkrt reads, checked for its type
    // and range (tinygltf skips what has the wrong type). JSON that does not parse is left to tinygltf to
    // describe.
    const bool binary = hasGlbMagic(path);
    if (binary) checkGlbVersion(path);
    nlohmann::json document = readGltfJson(path, binary);
    bool rewritten = false;
    if (!document.is_discarded()) {
        if (const auto extension = unsupportedRequiredExtension(document))
            throw SceneError(path + ": requires extension " + *extension + ", which vkrt does not support");
        validateGltfJson(document, path);
        rewritten = stubCompressedData(document);
    }

    tinygltf::TinyGLTF reader;
    reader.SetImageLoader(loadGltfImage, nullptr);
    reader.SetFsCallbacks(
        {tinygltf::FileExists, tinygltf::ExpandFilePath, readRegularFile, tinygltf::WriteWholeFile, nullptr});
    tinygltf::Model model;
    std::string error, warning;
    bool ok = false;
    if (rewritten) {
        // tinygltf reads the changed JSON (and a GLB's other chunks as they are) from memory.
        const std::string directory = std::filesystem::path(path).parent_path().string();
        const std::string text = document.dump();
        if (binary) {
            const std::string glb = replaceGlbJson(path, text);
            ok = reader.LoadBinaryFromMemory(&model, &error, &warning,
                                             reinterpret_cast<const unsigned char*>(glb.data()),
                                             static_cast<unsigned int>(glb.size()), directory);
        } else {
            ok = reader.LoadASCIIFromString(&model, &error, &warning, text.data(),
                                            static_cast<unsigned int>(text.size()), directory);
        }
    } else {
        ok = binary ? reader.LoadBinaryFromFile(&model, &error, &warning, path)
                    : reader.LoadASCIIFromFile(&model, &error, &warning, path);
    }
    if (!ok || !error.empty()) {
        std::string message = error.empty() ? "not a valid glTF file" : error;
        // tinygltf's messages can span lines; the command line reports one.
        std::replace(message.begin(), message.end(), '\n', ' ');
        while (!message.empty() && message.back() == ' ') message.pop_back();
        throw SceneError(path + ": " + message);
    }
    decompressMeshes(model, path);
    GltfConverter converter(model, path, options);
    return converter.convert();
}

}  // namespace vkrt
