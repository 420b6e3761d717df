// glTF mesh primitives to world-space triangles. Each mesh's primitives are decoded once (accessors read,
// indices checked, strips and fans unrolled, material resolved) and the decoded data is then placed once
// per node instance.
#pragma once

#include <array>
#include <cstdint>
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
    std::vector<std::array<uint32_t, 3>> faces;  // vertex indices, counter-clockwise
    uint32_t material = 0;
};

class MeshInstancer {
  public:
    explicit MeshInstancer(GltfContext& context) : context_(context) {}

    // Appends mesh `meshIndex` placed by `poses` (the shutter's opening, then the end of each motion
    // segment): its triangles, their shading and their later poses.
    void addInstance(int meshIndex, const std::vector<glm::dmat4>& poses);

    // Warnings for what instances skipped: degenerate triangles and point or line primitives.
    void warnAboutSkipped();

  private:
    DecodedPrimitive decode(int meshIndex, size_t primitiveIndex);
    // TANGENT, or tangents derived from the normal texture's coordinates, for a normal-mapped primitive.
    void decodeTangents(const tinygltf::Primitive& primitive, DecodedPrimitive& decoded);
    void place(const DecodedPrimitive& primitive, const std::vector<glm::dmat4>& poses);
    // The file's (or derived) tangents of a face, placed in the world.
    static std::array<glm::vec4, 3> placedTangents(const std::vector<float>& tangents,
                                                   const std::array<uint32_t, 3>& face, const glm::dmat3& linear,
                                                   bool mirrored);
    // The frame of a flat face (a primitive without normals), from its placed corners.
    std::array<glm::vec4, 3> flatTangents(const DecodedPrimitive& primitive, const Triangle& triangle,
                                          const std::array<uint32_t, 3>& face, const glm::vec3& geometric);

    GltfContext& context_;
    // Decoded primitives by mesh index, filled in order by the mesh's first instance.
    std::map<int, std::vector<DecodedPrimitive>> decoded_;
    size_t degenerateTriangles_ = 0;
    std::set<int> skippedModes_;
};

}  // namespace vkrt
