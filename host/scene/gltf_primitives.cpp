#include "scene/gltf_primitives.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>
#include <glm/gtc/type_ptr.hpp>

#include "common/memory_need.h"
#include "scene/gltf_materials.h"
#include "scene/tangent_frames.h"

namespace vkrt {

void MeshInstancer::addInstance(int meshIndex, const std::vector<InstancePose>& poses) {
    // Decode each primitive on the mesh's first instance, placing it before decoding the next, so that
    // errors come in the order the file's content meets them; later instances only place.
    std::vector<DecodedPrimitive>& primitives = decoded_[meshIndex];
    const size_t primitiveCount = context_.model.meshes[meshIndex].primitives.size();
    for (size_t p = 0; p < primitiveCount; ++p) {
        if (p == primitives.size()) primitives.push_back(decode(meshIndex, p));
        place(primitives[p], poses);
    }
}

void MeshInstancer::warnAboutSkipped() {
    if (degenerateTriangles_ > 0) {
        context_.warn(std::to_string(degenerateTriangles_) + " degenerate (zero-area) triangle(s) skipped");
    }
    for (int mode : skippedModes_) {
        context_.warn("primitives with mode " + std::to_string(mode) +
                      " (points or lines) skipped: vkrt renders triangles");
    }
    for (const std::string& name : ignoredTargetAttributes_)
        context_.warn("morph targets' " + name +
                      " displacements are ignored (vkrt morphs POSITION, NORMAL and TANGENT)");
}

DecodedPrimitive MeshInstancer::decode(int meshIndex, size_t primitiveIndex) {
    const tinygltf::Mesh& mesh = context_.model.meshes[meshIndex];
    const tinygltf::Primitive& primitive = mesh.primitives[primitiveIndex];
    DecodedPrimitive decoded;
    decodingBytes_ = 0;
    decoded.where = describe("mesh", meshIndex, mesh.name) + " primitive " + std::to_string(primitiveIndex);
    const std::string& where = decoded.where;

    // Triangles only: points and lines are skipped with a warning.
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= 3) {
        skippedModes_.insert(mode);
        decoded.skipped = true;
        return decoded;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        context_.fail(where + " has an invalid mode " + std::to_string(mode));
    }

    // Read the vertex attributes.
    auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) {
        // glTF 2.0 3.7.2.1: a primitive without positions (an extension may supply them) is not rendered.
        context_.warn(where + " has no POSITION attribute; it is left out");
        decoded.skipped = true;
        return decoded;
    }
    decoded.positions = readCountedFloats(position->second, 3, where + " POSITION");
    const std::vector<float>& positions = decoded.positions;
    const size_t vertexCount = positions.size() / 3;
    for (size_t i = 0; i < positions.size(); ++i) {
        if (!std::isfinite(positions[i])) {
            context_.fail(where + " POSITION has a non-finite value at vertex " + std::to_string(i / 3));
        }
    }
    if (auto it = primitive.attributes.find("NORMAL"); it != primitive.attributes.end()) {
        decoded.normals = readCountedFloats(it->second, 3, where + " NORMAL");
        if (decoded.normals.size() != positions.size())
            context_.fail(where + " NORMAL and POSITION counts differ");
    }
    for (const char* set : {"TEXCOORD_0", "TEXCOORD_1"}) {
        auto it = primitive.attributes.find(set);
        if (it == primitive.attributes.end()) continue;
        std::vector<float>& uvs = set[9] == '0' ? decoded.uvs : decoded.uvs1;
        uvs = readCountedFloats(it->second, 2, where + " " + set);
        if (uvs.size() / 2 != vertexCount) context_.fail(where + " " + set + " and POSITION counts differ");
        for (size_t i = 0; i < uvs.size(); ++i) {
            if (!std::isfinite(uvs[i]))
                context_.fail(where + " " + set + " has a non-finite value at vertex " +
                              std::to_string(i / 2));
        }
    }
    if (auto it = primitive.attributes.find("COLOR_0"); it != primitive.attributes.end()) {
        // VEC3 or VEC4, float or normalized integers, in [0, 1]; RGB gets alpha 1.
        const bool rgba = it->second >= 0 && it->second < static_cast<int>(context_.model.accessors.size()) &&
                          context_.model.accessors[it->second].type == TINYGLTF_TYPE_VEC4;
        const int components = rgba ? 4 : 3;
        const std::vector<float> colors = readCountedFloats(it->second, components, where + " COLOR_0");
        if (colors.size() / components != vertexCount)
            context_.fail(where + " COLOR_0 and POSITION counts differ");
        holdWhileDecoding(4.0 * sizeof(float) * vertexCount, 0.0, where + " COLOR_0");
        for (size_t v = 0; v < vertexCount; ++v) {
            for (int c = 0; c < 4; ++c) {
                const float value = c < components ? colors[components * v + c] : 1.0f;
                if (!std::isfinite(value))
                    context_.fail(where + " COLOR_0 has a non-finite value at vertex " + std::to_string(v));
                decoded.colors.push_back(std::clamp(value, 0.0f, 1.0f));
            }
        }
    }

    // Read and check the indices; without an accessor, the vertices in order.
    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
        indices = readCountedUnsigned(primitive.indices, 1, where + " indices");
        for (size_t i = 0; i < indices.size(); ++i) {
            if (indices[i] >= vertexCount) {
                context_.fail(where + " index " + std::to_string(indices[i]) + " at position " +
                              std::to_string(i) + " is out of range (the primitive has " +
                              std::to_string(vertexCount) + " vertices)");
            }
        }
    } else {
        holdWhileDecoding(static_cast<double>(sizeof(uint32_t)) * vertexCount, 0.0, where + " indices");
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
    }

    // Triangle list from strips and fans (glTF 2.0 section 3.7.2.1).
    std::vector<std::array<uint32_t, 3>>& faces = decoded.faces;
    const size_t faceCount = mode == TINYGLTF_MODE_TRIANGLES ? indices.size() / 3
                             : indices.size() > 2            ? indices.size() - 2
                                                             : 0;
    holdWhileDecoding(static_cast<double>(sizeof(faces[0])) * faceCount, 0.0, where + " triangles");
    faces.reserve(faceCount);
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

    // Resolve the material; glTF's default when the primitive names none.
    if (primitive.material < 0) {
        decoded.material = defaultMaterial(context_);
    } else if (primitive.material >= static_cast<int>(context_.model.materials.size())) {
        context_.fail(where + " refers to material " + std::to_string(primitive.material) +
                      ", which does not exist");
    } else {
        decoded.material = static_cast<uint32_t>(primitive.material);
    }
    // A texture that reads the second set where the primitive has none reads the first (the glTF validator
    // calls it an error; vkrt says so and renders): the first set is the primitive's second too, for its
    // textures, its vertex tangent frames and its derived ones alike. A texture that reads a set the
    // primitive lacks altogether reads (0, 0), and vkrt says that too.
    const auto readsSet = [&](int set) {
        for (const TextureSlot* slot : context_.scene.materials[decoded.material].textureSlots())
            if (slot->used() && slot->texCoord == set) return true;
        return false;
    };
    if (decoded.uvs.empty() && readsSet(0)) {
        context_.warn(where + " has no TEXCOORD_0, which its material's textures read; they read (0, 0)");
    }
    if (decoded.uvs1.empty() && readsSet(1)) {
        context_.warn(where +
                      (decoded.uvs.empty()
                           ? " has no TEXCOORD_1, which its material's textures read; they read (0, 0)"
                           : " has no TEXCOORD_1, which its material's textures read; they read TEXCOORD_0"));
        holdWhileDecoding(static_cast<double>(sizeof(float)) * decoded.uvs.size(), 0.0,
                          where + " TEXCOORD_1");
        decoded.uvs1 = decoded.uvs;
    }
    decodeTangents(primitive, decoded);
    decodeDeformation(meshIndex, primitive, decoded);
    const bool reshaped =
        std::any_of(decoded.targets.begin(), decoded.targets.end(),
                    [](const MorphTarget& t) { return !t.positions.empty() || !t.normals.empty(); });
    if (!reshaped) decoded.tangentUvs = {};
    keepUsedVertices(decoded);
    // The vertices' other attributes are at most three per triangle, whose memory is counted; their morph
    // targets and skin influences, any number per vertex, and the texture coordinates that a morphed mesh's
    // tangents are derived from again, are counted for the rest of the load.
    uint64_t deformationBytes = sizeof(uint32_t) * decoded.joints.size() +
                                sizeof(float) * (decoded.jointWeights.size() + decoded.tangentUvs.size());
    for (const MorphTarget& target : decoded.targets)
        deformationBytes +=
            sizeof(float) * (target.positions.size() + target.normals.size() + target.tangents.size());
    if (reserve_ && deformationBytes > 0)
        reserve_(deformationBytes, where + " morph targets and skin influences");
    return decoded;
}

void MeshInstancer::holdWhileDecoding(double keptBytes, double passingBytes, const std::string& what) {
    if (checkDecoding_)
        checkDecoding_(saturatedBytes(static_cast<double>(decodingBytes_) + keptBytes + passingBytes), what);
    decodingBytes_ = saturatedBytes(static_cast<double>(decodingBytes_) + keptBytes);
}

std::vector<float> MeshInstancer::readCountedFloats(int accessor, int components, const std::string& what) {
    // The reader builds doubles beside the floats it returns, and frees them when it does.
    const double values = static_cast<double>(context_.accessors.count(accessor, what)) * components;
    holdWhileDecoding(values * sizeof(float), values * sizeof(double), what);
    return context_.accessors.readFloats(accessor, components, what);
}

std::vector<uint32_t> MeshInstancer::readCountedUnsigned(int accessor, int components,
                                                         const std::string& what) {
    const double values = static_cast<double>(context_.accessors.count(accessor, what)) * components;
    holdWhileDecoding(values * sizeof(uint32_t), values * sizeof(double), what);
    return context_.accessors.readUnsigned(accessor, components, what);
}

bool MeshInstancer::liveTarget(int meshIndex, size_t target) const {
    if (!liveTargets_) return true;
    const auto live = liveTargets_->find(meshIndex);
    return live != liveTargets_->end() && target < live->second.size() && live->second[target];
}

void MeshInstancer::decodeDeformation(int meshIndex, const tinygltf::Primitive& primitive,
                                      DecodedPrimitive& decoded) {
    const std::string& where = decoded.where;
    const size_t vertexCount = decoded.positions.size() / 3;
    // Each weighed target's displacements of the attributes the primitive has; other attributes are passed
    // over, once said. A target no node weighs is left empty.
    for (size_t t = 0; t < primitive.targets.size(); ++t) {
        MorphTarget target;
        if (!liveTarget(meshIndex, t)) {
            decoded.targets.push_back(std::move(target));
            continue;
        }
        for (const auto& [name, accessor] : primitive.targets[t]) {
            const std::string what = where + " morph target " + std::to_string(t) + " " + name;
            std::vector<float>* values =
                name == "POSITION"  ? &target.positions
                : name == "NORMAL"  ? (decoded.normals.empty() ? nullptr : &target.normals)
                : name == "TANGENT" ? (decoded.tangents.empty() ? nullptr : &target.tangents)
                                    : nullptr;
            if (!values) {
                if (name != "NORMAL" && name != "TANGENT") ignoredTargetAttributes_.insert(name);
                continue;
            }
            *values = readCountedFloats(accessor, 3, what);
            if (values->size() != decoded.positions.size())
                context_.fail(what + " and POSITION counts differ");
            for (size_t i = 0; i < values->size(); ++i) {
                if (!std::isfinite((*values)[i]))
                    context_.fail(what + " has a non-finite value at vertex " + std::to_string(i / 3));
            }
        }
        decoded.targets.push_back(std::move(target));
    }
    // Joints and their weights, four per set, every set the primitive has (glTF 2.0 section 3.7.3.2 sets no
    // limit). A mesh no node skins keeps its vertices where its nodes put them, and its JOINTS and WEIGHTS
    // are not read.
    if (skinnedMeshes_ && !skinnedMeshes_->count(meshIndex)) return;
    const int sets = skinSetCount(primitive, where);
    if (sets == 0) return;
    decoded.influences = 4 * sets;
    const size_t influences = static_cast<size_t>(decoded.influences);
    holdWhileDecoding(static_cast<double>(sizeof(uint32_t) + sizeof(float)) * influences * vertexCount, 0.0,
                      where + " skin influences");
    decoded.joints.resize(influences * vertexCount);
    decoded.jointWeights.resize(influences * vertexCount);
    for (int set = 0; set < sets; ++set) {
        const std::string jointsName = "JOINTS_" + std::to_string(set);
        const std::string weightsName = "WEIGHTS_" + std::to_string(set);
        const std::vector<uint32_t> jointSet =
            readCountedUnsigned(primitive.attributes.at(jointsName), 4, where + " " + jointsName);
        const std::vector<float> weightSet =
            readCountedFloats(primitive.attributes.at(weightsName), 4, where + " " + weightsName);
        if (jointSet.size() != 4 * vertexCount || weightSet.size() != 4 * vertexCount)
            context_.fail(where + " " + jointsName + ", " + weightsName + " and POSITION counts differ");
        for (size_t i = 0; i < weightSet.size(); ++i) {
            if (!(weightSet[i] >= 0.0f) || !std::isfinite(weightSet[i]))
                context_.fail(where + " " + weightsName + " has a negative or non-finite value at vertex " +
                              std::to_string(i / 4));
        }
        // Interleaved per vertex: set 0's four influences, then set 1's, and so on.
        for (size_t v = 0; v < vertexCount; ++v) {
            std::copy_n(jointSet.begin() + static_cast<std::ptrdiff_t>(4 * v), 4,
                        decoded.joints.begin() + static_cast<std::ptrdiff_t>(influences * v + 4 * set));
            std::copy_n(weightSet.begin() + static_cast<std::ptrdiff_t>(4 * v), 4,
                        decoded.jointWeights.begin() + static_cast<std::ptrdiff_t>(influences * v + 4 * set));
        }
    }
}

int MeshInstancer::skinSetCount(const tinygltf::Primitive& primitive, const std::string& where) const {
    // The highest set number named by a JOINTS_n or WEIGHTS_n attribute.
    int sets = 0;
    for (const auto& attribute : primitive.attributes) {
        const std::string& name = attribute.first;
        for (const std::string prefix : {"JOINTS_", "WEIGHTS_"}) {
            if (name.compare(0, prefix.size(), prefix) != 0) continue;
            const std::string number = name.substr(prefix.size());
            const bool decimal =
                !number.empty() && number.size() <= 9 &&
                std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
                (number == "0" || number[0] != '0');
            if (decimal) sets = std::max(sets, std::stoi(number) + 1);
        }
    }
    // Every set below it has both (glTF 2.0 section 3.7.2.1 numbers the sets from 0 without gaps).
    for (int set = 0; set < sets; ++set) {
        const std::string joints = "JOINTS_" + std::to_string(set),
                          weights = "WEIGHTS_" + std::to_string(set);
        const bool hasJoints = primitive.attributes.count(joints) > 0;
        const bool hasWeights = primitive.attributes.count(weights) > 0;
        if (hasJoints != hasWeights)
            context_.fail(where + " has one of " + joints + " and " + weights + " without the other");
        if (!hasJoints)
            context_.fail(where + " has JOINTS_" + std::to_string(sets - 1) + " or WEIGHTS_" +
                          std::to_string(sets - 1) + " but not " + joints + " and " + weights +
                          " (the sets are numbered from 0 without gaps)");
    }
    return sets;
}

void MeshInstancer::decodeTangents(const tinygltf::Primitive& primitive, DecodedPrimitive& decoded) {
    const TextureSlot& normalTexture = context_.scene.materials[decoded.material].tangentFrameSlot();
    decoded.normalMapped = normalTexture.used();
    // Without normals the triangles are flat and the file's tangents are ignored (glTF 2.0, 3.7.2.1):
    // place() derives one frame per face.
    if (!decoded.normalMapped || decoded.normals.empty()) return;
    const std::string& where = decoded.where;
    const size_t vertexCount = decoded.positions.size() / 3;
    if (auto it = primitive.attributes.find("TANGENT"); it != primitive.attributes.end()) {
        decoded.tangents = readCountedFloats(it->second, 4, where + " TANGENT");
        if (decoded.tangents.size() / 4 != vertexCount) context_.fail(where + " TANGENT and POSITION counts differ");
        for (size_t i = 0; i < decoded.tangents.size(); ++i) {
            if (!std::isfinite(decoded.tangents[i]))
                context_.fail(where + " TANGENT has a non-finite value at vertex " + std::to_string(i / 4));
        }
        return;
    }
    // The texture coordinates the normal texture reads; without them the normal texture is one texel.
    const std::vector<float>& uvs = normalTexture.texCoord == 1 ? decoded.uvs1 : decoded.uvs;
    if (uvs.empty()) return;
    // As its KHR_texture_transform turns, mirrors and scales them (the offset moves no direction): the frame
    // is the image's, whatever writes the mapping. Taken from the mesh's coordinates alone, a normal map
    // mirrored by the transform showed its ridges as valleys, and one turned by it was lit from the side.
    const std::array<glm::vec2, 2> rows = normalTexture.linearRows();
    // The tangents and mapped coordinates kept (the latter where targets morph the mesh), beside the two sums
    // per vertex that derive them.
    holdWhileDecoding(10.0 * sizeof(float) * vertexCount + decoded.faces.size() / 8.0,
                      static_cast<double>(4 * sizeof(glm::dvec3)) * vertexCount, where + " derived tangents");
    std::vector<float> mapped(uvs.size());
    for (size_t i = 0; i + 1 < uvs.size(); i += 2) {
        const glm::vec2 uv(uvs[i], uvs[i + 1]);
        mapped[i] = glm::dot(rows[0], uv);
        mapped[i + 1] = glm::dot(rows[1], uv);
    }
    VertexTangents derived = vertexTangents(decoded.positions, decoded.normals, mapped, decoded.faces);
    decoded.tangents = std::move(derived.frames);
    decoded.mirroredTangents = std::move(derived.mirroredFrames);
    decoded.mirroredFaces = std::move(derived.mirroredFaces);
    decoded.tangentUvs = std::move(mapped);  // dropped again unless morph targets move the mesh (decode)
}

std::array<glm::vec4, 3> MeshInstancer::flatTangents(const DecodedPrimitive& primitive, const Triangle& triangle,
                                                     const std::array<uint32_t, 3>& face,
                                                     const glm::vec3& geometric) {
    const TextureSlot& slot = context_.scene.materials[primitive.material].tangentFrameSlot();
    const std::vector<float>& uvs = slot.texCoord == 1 ? primitive.uvs1 : primitive.uvs;
    if (uvs.empty()) return {};
    // Through the normal texture's transform, as decodeTangents takes them.
    const std::array<glm::vec2, 2> rows = slot.linearRows();
    std::array<glm::dvec2, 3> uv;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 meshUv(uvs[2 * face[k]], uvs[2 * face[k] + 1]);
        uv[k] = glm::dvec2(glm::dot(glm::dvec2(rows[0]), meshUv), glm::dot(glm::dvec2(rows[1]), meshUv));
    }
    const glm::vec4 frame = faceTangent({glm::dvec3(triangle.v0), glm::dvec3(triangle.v1), glm::dvec3(triangle.v2)},
                                        uv, glm::dvec3(geometric));
    return {frame, frame, frame};
}

namespace {

// `values` (`stride` per vertex) of the vertices `used` lists, in its order.
template <typename T>
void keepVertices(std::vector<T>& values, size_t stride, const std::vector<uint32_t>& used) {
    if (values.empty()) return;
    std::vector<T> kept(used.size() * stride);
    for (size_t i = 0; i < used.size(); ++i)
        std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(used[i] * stride), stride,
                    kept.begin() + static_cast<std::ptrdiff_t>(i * stride));
    values = std::move(kept);
}

}  // namespace

void MeshInstancer::keepUsedVertices(DecodedPrimitive& decoded) {
    // Placing works on every vertex a primitive has, once per pose and instance: a sparse accessor that
    // claims millions of vertices for one triangle (a file of a few KB) took minutes. Only the faces'
    // vertices stay.
    const size_t vertexCount = decoded.positions.size() / 3;
    std::vector<uint32_t> index(vertexCount, UINT32_MAX), used;
    for (const auto& face : decoded.faces) {
        for (uint32_t v : face) {
            if (index[v] != UINT32_MAX) continue;
            index[v] = 0;
            used.push_back(v);
        }
    }
    if (used.size() == vertexCount) return;
    std::sort(used.begin(), used.end());  // the file's order, so that nothing else changes
    for (size_t i = 0; i < used.size(); ++i) index[used[i]] = static_cast<uint32_t>(i);
    for (auto& face : decoded.faces)
        for (uint32_t& v : face) v = index[v];
    keepVertices(decoded.positions, 3, used);
    keepVertices(decoded.normals, 3, used);
    keepVertices(decoded.uvs, 2, used);
    keepVertices(decoded.colors, 4, used);
    keepVertices(decoded.uvs1, 2, used);
    keepVertices(decoded.tangents, 4, used);
    keepVertices(decoded.mirroredTangents, 4, used);
    keepVertices(decoded.tangentUvs, 2, used);
    for (MorphTarget& target : decoded.targets) {
        keepVertices(target.positions, 3, used);
        keepVertices(target.normals, 3, used);
        keepVertices(target.tangents, 3, used);
    }
    keepVertices(decoded.joints, static_cast<size_t>(decoded.influences), used);
    keepVertices(decoded.jointWeights, static_cast<size_t>(decoded.influences), used);
}

namespace {

// Attribute `attribute` (`stride` floats per vertex, its first three displaced) of vertex `v`, with the morph
// targets' displacements at `weights`.
glm::dvec3 morphed(const std::vector<float>& base, int stride, const std::vector<MorphTarget>& targets,
                   std::vector<float> MorphTarget::*attribute, const std::vector<double>& weights,
                   uint32_t v) {
    const float* b = &base[static_cast<size_t>(stride) * v];
    glm::dvec3 value(b[0], b[1], b[2]);
    for (size_t t = 0; t < targets.size() && t < weights.size(); ++t) {
        const std::vector<float>& delta = targets[t].*attribute;
        if (delta.empty() || weights[t] == 0.0) continue;
        value += weights[t] * glm::dvec3(delta[3 * v], delta[3 * v + 1], delta[3 * v + 2]);
    }
    return value;
}

// Every vertex's `attribute` (3 floats per vertex) with the morph targets' displacements at `weights`.
std::vector<float> morphedAll(const std::vector<float>& base, const std::vector<MorphTarget>& targets,
                              std::vector<float> MorphTarget::*attribute,
                              const std::vector<double>& weights) {
    std::vector<float> result(base.size());
    for (size_t v = 0; v < base.size() / 3; ++v) {
        const glm::dvec3 value = morphed(base, 3, targets, attribute, weights, static_cast<uint32_t>(v));
        for (int c = 0; c < 3; ++c) result[3 * v + c] = static_cast<float>(value[c]);
    }
    return result;
}

// Whether every corner coordinate is finite (each on its own: their float sum overflowed for finite corners
// near float's range).
bool cornersFinite(const Triangle& t) {
    for (const glm::vec3& corner : {t.v0, t.v1, t.v2})
        if (!std::isfinite(corner.x) || !std::isfinite(corner.y) || !std::isfinite(corner.z)) return false;
    return true;
}

// The transform of vertex `v` of a skinned primitive at `pose`: its joints' matrices weighted (glTF 2.0
// section 3.7.3.3), the weights scaled to sum to 1 (8-bit weights rarely sum to it exactly); the node's own
// transform for a vertex that no joint weighs.
glm::dmat4 skinTransform(const DecodedPrimitive& primitive, const InstancePose& pose, uint32_t v) {
    const size_t first = static_cast<size_t>(primitive.influences) * v;
    double total = 0.0;
    for (int i = 0; i < primitive.influences; ++i) total += primitive.jointWeights[first + i];
    if (!(total > 0.0)) return pose.world;
    glm::dmat4 blend(0.0);
    for (int i = 0; i < primitive.influences; ++i) {
        const double weight = primitive.jointWeights[first + i];
        if (weight != 0.0) blend += (weight / total) * (*pose.joints)[primitive.joints[first + i]];
    }
    return blend;
}

}  // namespace

size_t MeshInstancer::morphTargetCount(int meshIndex) const {
    // glTF 2.0 section 3.7.2.2: every primitive of a mesh has the same number of targets, the number of
    // weights the mesh and its nodes give.
    const tinygltf::Mesh& mesh = context_.model.meshes[meshIndex];
    if (mesh.primitives.empty()) return 0;
    const size_t count = mesh.primitives[0].targets.size();
    for (size_t p = 1; p < mesh.primitives.size(); ++p) {
        if (mesh.primitives[p].targets.size() != count) {
            context_.fail(describe("mesh", meshIndex, mesh.name) + " primitive " + std::to_string(p) +
                          " has " + std::to_string(mesh.primitives[p].targets.size()) +
                          " morph target(s) and primitive 0 " + std::to_string(count) +
                          "; glTF 2.0 section 3.7.2.2 wants the same number in each");
        }
    }
    return count;
}

void MeshInstancer::place(const DecodedPrimitive& primitive, const std::vector<InstancePose>& poses) {
    if (primitive.skipped) return;
    const std::string& where = primitive.where;
    const std::vector<float>& positions = primitive.positions;
    const std::vector<float>& normals = primitive.normals;
    const std::vector<float>& uvs = primitive.uvs;
    const uint32_t material = primitive.material;
    const InstancePose& opening = poses[0];

    // A primitive is skinned when its node has joints and it has weights for them, and morphed when one of
    // its targets has a weight; otherwise the node's transform places it rigidly.
    const bool skinned = primitive.influences > 0 && opening.joints != nullptr;
    if (skinned) {
        for (uint32_t joint : primitive.joints) {
            if (joint >= opening.joints->size()) {
                context_.fail(where + " JOINTS refers to joint " + std::to_string(joint) +
                              "; the node's skin has " + std::to_string(opening.joints->size()));
            }
        }
    }
    bool morphs = false;
    for (const InstancePose& pose : poses)
        for (double weight : pose.weights) morphs |= weight != 0.0;
    morphs &= !primitive.targets.empty();
    // Every vertex placed once for a pose (a vertex is a corner of about six triangles).
    const size_t vertexCount = positions.size() / 3;
    std::vector<glm::vec3> placed(vertexCount);
    // A skinned vertex's linear map at the opening, for its normal and tangent.
    std::vector<glm::dmat3> skinLinear(skinned ? vertexCount : 0);
    auto placeVertices = [&](const InstancePose& pose, bool keepLinear) {
        for (size_t v = 0; v < vertexCount; ++v) {
            const uint32_t vertex = static_cast<uint32_t>(v);
            const glm::dvec4 p(
                morphs
                    ? morphed(positions, 3, primitive.targets, &MorphTarget::positions, pose.weights, vertex)
                    : glm::dvec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]),
                1.0);
            if (skinned) {
                const glm::dmat4 transform = skinTransform(primitive, pose, vertex);
                placed[v] = glm::vec3(transform * p);
                if (keepLinear) skinLinear[v] = glm::dmat3(transform);
            } else {
                placed[v] = glm::vec3(pose.world * p);
            }
        }
    };
    placeVertices(opening, true);

    // Frames derived from the texture coordinates come from the mesh as its targets morph it at the opening
    // (glTF 2.0 section 3.7.2.1 derives tangents from the positions and normals the primitive has): the rest
    // pose's frames left a normal texture facing as the unmorphed mesh faced (a quad turned 90 degrees by its
    // target was lit as if unturned).
    const bool rederived = morphs && !primitive.tangentUvs.empty();
    VertexTangents morphedFrames;
    if (rederived) {
        morphedFrames =
            vertexTangents(morphedAll(positions, primitive.targets, &MorphTarget::positions, opening.weights),
                           morphedAll(normals, primitive.targets, &MorphTarget::normals, opening.weights),
                           primitive.tangentUvs, primitive.faces);
    }
    const std::vector<float>& tangentFrames = rederived ? morphedFrames.frames : primitive.tangents;
    const std::vector<float>& mirroredFrames =
        rederived ? morphedFrames.mirroredFrames : primitive.mirroredTangents;
    const std::vector<bool>& mirroredFaces =
        rederived ? morphedFrames.mirroredFaces : primitive.mirroredFaces;

    // At the opening, the maps of the vertices' directions: one for a rigid placement, one per corner when
    // skinned. Mirroring reverses the winding.
    const glm::dmat3 rigidLinear(opening.world);
    const glm::dmat3 rigidNormalMatrix = glm::transpose(glm::inverse(rigidLinear));
    const size_t firstTriangle = context_.scene.triangles.size();
    std::vector<std::array<uint32_t, 3>> kept;  // the faces placed, as wound, for their later poses
    for (size_t faceIndex = 0; faceIndex < primitive.faces.size(); ++faceIndex) {
        std::array<uint32_t, 3> face = primitive.faces[faceIndex];
        std::array<glm::dmat3, 3> linear{rigidLinear, rigidLinear, rigidLinear};
        std::array<glm::dmat3, 3> normalMatrix{rigidNormalMatrix, rigidNormalMatrix, rigidNormalMatrix};
        double determinant = glm::determinant(rigidLinear);
        if (skinned) {
            determinant = 0.0;
            for (int k = 0; k < 3; ++k) {
                linear[k] = skinLinear[face[k]];
                normalMatrix[k] = glm::transpose(glm::inverse(linear[k]));
                determinant += glm::determinant(linear[k]);
            }
        }
        const bool mirrored = determinant < 0.0;
        if (mirrored) {
            std::swap(face[1], face[2]);
            std::swap(linear[1], linear[2]);
            std::swap(normalMatrix[1], normalMatrix[2]);
        }
        // Place the triangle at the shutter's opening; drop it when it has no area.
        Triangle triangle{placed[face[0]], placed[face[1]], placed[face[2]], material};
        if (!cornersFinite(triangle)) {
            context_.fail(where + " has a vertex that its node transform moves out of floating-point range");
        }
        const glm::dvec3 cross = glm::cross(glm::dvec3(triangle.v1) - glm::dvec3(triangle.v0),
                                            glm::dvec3(triangle.v2) - glm::dvec3(triangle.v0));
        const double crossLength = glm::length(cross);
        if (!(crossLength > 0.0)) {
            ++degenerateTriangles_;
            continue;
        }
        // Shading normals (the geometric normal where the file has none or they vanish) and uvs.
        const glm::vec3 geometric(cross / crossLength);
        TriangleShading shading{};
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = face[k];
            shading.normal[k] = geometric;
            if (!normals.empty()) {
                const glm::dvec3 n =
                    normalMatrix[k] *
                    (morphs
                         ? morphed(normals, 3, primitive.targets, &MorphTarget::normals, opening.weights, v)
                         : glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]));
                const double length = glm::length(n);
                if (length > 0.0 && std::isfinite(length)) shading.normal[k] = glm::vec3(n / length);
            }
            if (!uvs.empty()) shading.uv[k] = glm::vec2(uvs[2 * v], uvs[2 * v + 1]);
        }
        if (!primitive.uvs1.empty()) {
            // The second texture coordinate set starts with this primitive: the triangles before it have
            // zeros.
            context_.scene.uv1.resize(context_.scene.triangles.size(), {});
            std::array<glm::vec2, 3> corner;
            for (int k = 0; k < 3; ++k) corner[k] = glm::make_vec2(&primitive.uvs1[2 * face[k]]);
            context_.scene.uv1.push_back(corner);
        }
        if (primitive.normalMapped) {
            // Tangent frames start with this primitive: the triangles before it have none. A tangent is a
            // direction along the surface: it moves with the linear part of the transform, and a mirroring
            // transform flips the handedness of the frame, so the bitangent's sign flips with it.
            context_.scene.tangents.resize(context_.scene.triangles.size(), {});
            std::array<glm::vec4, 3> frame{};
            if (primitive.tangents.empty()) {
                frame = flatTangents(primitive, triangle, face, geometric);
            } else {
                // Derived frames: the one of the face's own kind (the image mirrored on it or not).
                const std::vector<float>& frames =
                    !mirroredFaces.empty() && mirroredFaces[faceIndex] ? mirroredFrames : tangentFrames;
                for (int k = 0; k < 3; ++k) {
                    const uint32_t v = face[k];
                    const glm::dvec3 t =
                        linear[k] * (rederived
                                         ? glm::dvec3(frames[4 * v], frames[4 * v + 1], frames[4 * v + 2])
                                         : morphed(frames, 4, primitive.targets, &MorphTarget::tangents,
                                                   opening.weights, v));
                    const double length = glm::length(t);
                    if (!(length > 0.0) || !std::isfinite(length))
                        continue;  // zero: no frame, no perturbation
                    const double w = (frames[4 * v + 3] < 0.0f ? -1.0 : 1.0) * (mirrored ? -1.0 : 1.0);
                    frame[k] = glm::vec4(glm::dvec4(t / length, w));
                }
            }
            context_.scene.tangents.push_back(frame);
        }
        if (!primitive.colors.empty()) {
            // Vertex colours start with this primitive: the triangles before it are white.
            std::vector<std::array<glm::vec4, 3>>& colors = context_.scene.vertexColors;
            colors.resize(context_.scene.triangles.size(), kVertexColorWhite);
            std::array<glm::vec4, 3> corner;
            for (int k = 0; k < 3; ++k) corner[k] = glm::make_vec4(&primitive.colors[4 * face[k]]);
            colors.push_back(corner);
        }
        context_.scene.triangles.push_back(triangle);
        context_.scene.shading.push_back(shading);
        if (poses.size() > 1) kept.push_back(face);
    }
    // The placed triangles' later poses, one per motion segment end: pose k of the primitive's i-th triangle
    // is at i * segments + k - 1 past its first's.
    if (kept.empty()) return;
    const size_t segments = poses.size() - 1;
    std::vector<Triangle>& later = context_.scene.trianglePoses;
    const size_t firstPose = firstTriangle * segments;
    later.resize(firstPose + kept.size() * segments);
    for (size_t k = 1; k < poses.size(); ++k) {
        placeVertices(poses[k], false);
        for (size_t i = 0; i < kept.size(); ++i) {
            const std::array<uint32_t, 3>& face = kept[i];
            const Triangle pose{placed[face[0]], placed[face[1]], placed[face[2]], material};
            if (!cornersFinite(pose)) {
                context_.fail(where + " has a vertex that its animation moves out of floating-point range");
            }
            later[firstPose + i * segments + (k - 1)] = pose;
        }
    }
}

}  // namespace vkrt
