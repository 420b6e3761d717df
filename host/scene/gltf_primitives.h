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
    void place(const DecodedPrimitive& primitive, const std::vector<glm::dmat4>& poses);

    GltfContext& context_;
    // Decoded primitives by mesh index, filled in order by the mesh's first instance.
    std::map<int, std::vector<DecodedPrimitive>> decoded_;
    size_t degenerateTriangles_ = 0;
    std::set<int> skippedModes_;
};

}  // namespace vkrt
