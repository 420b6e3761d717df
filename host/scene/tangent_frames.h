// Tangent frames for normal mapping where a mesh gives none (glTF 2.0, 3.7.2.1: without TANGENT, tangents
// are derived from the texture coordinates the normal texture reads).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace vkrt {

// Derived tangent frames of a smooth mesh (vertexTangents), 4 floats per frame: the unit tangent, then the
// bitangent's sign w, bitangent = w * cross(normal, tangent). A vertex has two: one from its faces that show
// the image as it is, one from those that show it mirrored (their (u, v) turn the other way: a mirrored half
// of a model whose seam shares vertices with the other half), and each face takes the one of its own kind. A
// vertex whose faces are all of one kind has that frame in both.
struct VertexTangents {
    std::vector<float> frames;          // 4 per vertex: from its faces that show the image as it is
    std::vector<float> mirroredFrames;  // 4 per vertex: from its faces that show it mirrored
    std::vector<bool> mirroredFaces;    // per face: whether it shows the image mirrored
};

// Each triangle's dP/du and dP/dv are accumulated at its corners, weighted by the corner's angle, apart for
// the two kinds of face; then the tangent is made orthogonal to the vertex normal (Gram-Schmidt), and w says
// whether -dP/dv (the image's up: glTF's v grows downwards) agrees with cross(normal, tangent). This is the
// core of MikkTSpace (Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008) with its split of
// vertices at mirrored seams, not its other splits. (Averaged across a seam, the two halves' tangents
// cancelled: 45% of the pixels of a triangle beside one were lit as the other half's.) A vertex whose texture
// coordinates give no direction gets zero, which leaves its normal unperturbed.
VertexTangents vertexTangents(const std::vector<float>& positions, const std::vector<float>& normals,
                              const std::vector<float>& uvs,
                              const std::vector<std::array<uint32_t, 3>>& faces);

// The tangent frame of one flat triangle with geometric normal `normal` (zero when its texture coordinates
// give no direction).
glm::vec4 faceTangent(const std::array<glm::dvec3, 3>& corners, const std::array<glm::dvec2, 3>& uvs,
                      const glm::dvec3& normal);

}  // namespace vkrt
