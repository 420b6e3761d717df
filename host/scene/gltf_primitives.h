// glTF mesh primitives to world-space triangles. Each mesh's primitives are decoded once (accessors read,
// indices checked, strips and fans unrolled, material resolved) and the decoded data is then placed once
// per node instance: by the node's transform, or by its skin's joints, with its morph targets weighted.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf_context.h"
#include "scene/scene.h"

namespace tinygltf {
struct Primitive;
}

namespace vkrt {

// One morph target of a primitive (glTF 2.0 section 3.7.2.2): displacements of its vertices, each list
// empty where the target leaves that attribute alone.
struct MorphTarget {
    std::vector<float> positions;  // 3 per vertex
    std::vector<float> normals;    // 3 per vertex
    std::vector<float> tangents;   // 3 per vertex (the bitangent's sign stays)
};

// One primitive in its mesh's own space, as the accessors give it.
struct DecodedPrimitive {
    std::string where;                           // "mesh i ('name') primitive p", for messages
    bool skipped = false;                        // points or lines: nothing to place
    std::vector<float> positions;                // 3 per vertex
    std::vector<float> normals;                  // 3 per vertex, or empty
    std::vector<float> uvs;                      // TEXCOORD_0, 2 per vertex, or empty
    std::vector<float> colors;                   // COLOR_0 as RGBA, 4 per vertex, or empty
    std::vector<float> uvs1;                     // TEXCOORD_1, 2 per vertex, or empty
    bool normalMapped = false;                   // its material has a normal texture
    std::vector<float> tangents;                 // normal-mapped with normals: 4 per vertex (tangent_frames.h)
    std::vector<float> mirroredTangents;         // derived: the frames of the faces mirroredFaces marks
    std::vector<bool> mirroredFaces;             // derived: per face, whether it shows the image mirrored
    // Derived, where morph targets move the positions or normals the frames come from: the normal texture's
    // coordinates through its transform, 2 per vertex, to derive the frames again from the morphed mesh.
    std::vector<float> tangentUvs;
    std::vector<std::array<uint32_t, 3>> faces;  // vertex indices, counter-clockwise
    uint32_t material = 0;
    std::vector<MorphTarget> targets;  // morph targets, in the order of the mesh's weights
    // Skinning (glTF 2.0 section 3.7.3): JOINTS_n and WEIGHTS_n for every set n the primitive has,
    // interleaved per vertex, `influences` (4 per set) per vertex; empty for a primitive without them.
    int influences = 0;
    std::vector<uint32_t> joints;
    std::vector<float> jointWeights;
};

// Where one instance of a mesh is at one pose time (the shutter's opening or a motion segment's end).
struct InstancePose {
    glm::dmat4 world{1.0};           // the node's world transform
    const std::vector<glm::dmat4>* joints = nullptr;  // a skinned node's: world transform times inverse bind
    std::vector<double> weights;     // the morph targets' weights (the node's, else the mesh's, else zero)
};

class MeshInstancer {
  public:
    explicit MeshInstancer(GltfContext& context) : context_(context) {}

    // Appends mesh `meshIndex` placed by `poses` (the shutter's opening, then the end of each motion
    // segment): its triangles, their shading and their later poses. A skinned primitive's vertices follow
    // the poses' joints, which replace the node's transform (glTF 2.0 section 3.7.3.3).
    void addInstance(int meshIndex, const std::vector<InstancePose>& poses);

    // The number of morph targets each primitive of mesh `meshIndex` has (the count its weights must have);
    // throws SceneError when its primitives have different numbers.
    size_t morphTargetCount(int meshIndex) const;

    // By mesh, which morph targets some node weighs: the others are not read (all are, without this).
    void setLiveTargets(const std::map<int, std::vector<bool>>* live) { liveTargets_ = live; }
    // The meshes some node skins: the others' joints and weights are not read (all are, without this).
    void setSkinnedMeshes(const std::set<int>* skinned) { skinnedMeshes_ = skinned; }
    // Counts the host memory that decoded morph targets and skin influences take for the rest of the load
    // (throws when it is more than is available).
    void setReserve(std::function<void(uint64_t bytes, const std::string& what)> reserve) {
        reserve_ = std::move(reserve);
    }
    // Checks that `bytes`, held only while one primitive is decoded, fit in the host memory available beside
    // the scene's (throws when they do not).
    void setDecodingCheck(std::function<void(uint64_t bytes, const std::string& what)> check) {
        checkDecoding_ = std::move(check);
    }

    // Warnings for what instances skipped: degenerate triangles and point or line primitives.
    void warnAboutSkipped();

  private:
    DecodedPrimitive decode(int meshIndex, size_t primitiveIndex);
    // Whether some node weighs morph target `target` of mesh `meshIndex`.
    bool liveTarget(int meshIndex, size_t target) const;
    // TANGENT, or tangents derived from the normal texture's coordinates, for a normal-mapped primitive.
    void decodeTangents(const tinygltf::Primitive& primitive, DecodedPrimitive& decoded);
    // Drops the vertices no face uses, from every per-vertex list (renumbering the faces).
    static void keepUsedVertices(DecodedPrimitive& decoded);
    // Morph targets, and skinning's joints and weights, of a primitive.
    void decodeDeformation(int meshIndex, const tinygltf::Primitive& primitive, DecodedPrimitive& decoded);
    // How many JOINTS_n and WEIGHTS_n sets a primitive has; throws when one lacks its partner or a set is
    // missing below the highest.
    int skinSetCount(const tinygltf::Primitive& primitive, const std::string& where) const;
    // Counts `keptBytes` more held by the primitive being decoded, checking first that they fit with
    // `passingBytes` more beside them for a moment.
    void holdWhileDecoding(double keptBytes, double passingBytes, const std::string& what);
    // An accessor of the primitive being decoded, read as AccessorReader reads it once its memory is counted.
    std::vector<float> readCountedFloats(int accessor, int components, const std::string& what);
    std::vector<uint32_t> readCountedUnsigned(int accessor, int components, const std::string& what);
    void place(const DecodedPrimitive& primitive, const std::vector<InstancePose>& poses);
    // The frame of a flat face (a primitive without normals), from its placed corners.
    std::array<glm::vec4, 3> flatTangents(const DecodedPrimitive& primitive, const Triangle& triangle,
                                          const std::array<uint32_t, 3>& face, const glm::vec3& geometric);

    GltfContext& context_;
    // Decoded primitives by mesh index, filled in order by the mesh's first instance.
    std::map<int, std::vector<DecodedPrimitive>> decoded_;
    size_t degenerateTriangles_ = 0;
    std::set<int> skippedModes_;
    std::set<std::string> ignoredTargetAttributes_;  // morph targets' TEXCOORD_n, COLOR_n, ...
    const std::map<int, std::vector<bool>>* liveTargets_ = nullptr;
    const std::set<int>* skinnedMeshes_ = nullptr;
    std::function<void(uint64_t, const std::string&)> reserve_;
    std::function<void(uint64_t, const std::string&)> checkDecoding_;
    uint64_t decodingBytes_ = 0;  // what the primitive being decoded holds so far
};

}  // namespace vkrt
