// Tangent frames for normal mapping where a mesh gives none (glTF 2.0, 3.7.2.1: without TANGENT, tangents
// are derived from the texture coordinates the normal texture reads).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace vkrt {

// Per-vertex tangents of a smooth mesh (4 floats per vertex: the unit tangent, then the bitangent's sign w,
// bitangent = w * cross(normal, tangent)). Each triangle's dP/du and dP/dv are accumulated at its corners,
// weighted by the corner's angle, then the tangent is made orthogonal to the vertex normal (Gram-Schmidt);
// w says whether -dP/dv (the image's up: glTF's v grows downwards) agrees with cross(normal, tangent). This is the core of MikkTSpace (Mikkelsen, "Simulation
// of Wrinkled Surfaces Revisited", 2008) without its splitting of vertices whose triangles' frames disagree
// (mirrored UV seams that share vertices): such vertices get an averaged frame. A vertex whose texture
// coordinates give no direction gets zero, which leaves its normal unperturbed.
std::vector<float> vertexTangents(const std::vector<float>& positions, const std::vector<float>& normals,
                                  const std::vector<float>& uvs,
                                  const std::vector<std::array<uint32_t, 3>>& faces);

// The tangent frame of one flat triangle with geometric normal `normal` (zero when its texture coordinates
// give no direction).
glm::vec4 faceTangent(const std::array<glm::dvec3, 3>& corners, const std::array<glm::dvec2, 3>& uvs,
                      const glm::dvec3& normal);

}  // namespace vkrt
