#include "scene/scene_builder.h"

#include <array>
#include <cmath>
#include <cstring>
#include <unordered_set>

#include "shape_geometry.h"

namespace vkrt {
namespace {

// A triangle's corners rotated so the lexicographically smallest comes first (winding kept), as bits.
struct TriangleKey {
    std::array<uint32_t, 9> words;
    bool operator==(const TriangleKey& other) const { return words == other.words; }
};

struct TriangleKeyHash {
    size_t operator()(const TriangleKey& key) const {
        uint64_t hash = 1469598103934665603ull;
        for (uint32_t w : key.words) hash = (hash ^ w) * 1099511628211ull;
        return static_cast<size_t>(hash);
    }
};

bool lexicographicallyLess(const glm::vec3& a, const glm::vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

TriangleKey keyOf(const Triangle& t) {
    std::array<glm::vec3, 3> v = {t.v0, t.v1, t.v2};
    int first = 0;
    for (int i = 1; i < 3; ++i) {
        if (lexicographicallyLess(v[i], v[first])) first = i;
    }
    TriangleKey key{};
    for (int i = 0; i < 3; ++i) {
        const glm::vec3 p = v[(first + i) % 3] + glm::vec3(0.0f);  // + 0 turns -0 into +0
        std::memcpy(&key.words[3 * i], &p, sizeof(p));
    }
    return key;
}

}  // namespace

size_t removeDuplicateTriangles(Scene& scene) {
    std::unordered_set<TriangleKey, TriangleKeyHash> seen;
    seen.reserve(scene.triangles.size());
    size_t kept = 0;
    const size_t segments = static_cast<size_t>(scene.motionSegments);
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        // Moving triangles are kept: two that coincide at the shutter's opening may part later.
        bool still = true;
        for (size_t k = 0; k < segments; ++k)
            still = still && keyOf(scene.trianglePoses[i * segments + k]) == keyOf(scene.triangles[i]);
        if (still && !seen.insert(keyOf(scene.triangles[i])).second) continue;
        scene.triangles[kept] = scene.triangles[i];
        scene.shading[kept] = scene.shading[i];
        if (!scene.vertexColors.empty()) scene.vertexColors[kept] = scene.vertexColors[i];
        if (!scene.uv1.empty()) scene.uv1[kept] = scene.uv1[i];
        if (!scene.tangents.empty()) scene.tangents[kept] = scene.tangents[i];
        for (size_t k = 0; k < segments; ++k)
            scene.trianglePoses[kept * segments + k] = scene.trianglePoses[i * segments + k];
        ++kept;
    }
    const size_t removed = scene.triangles.size() - kept;
    scene.triangles.resize(kept);
    scene.shading.resize(kept);
    if (!scene.vertexColors.empty()) scene.vertexColors.resize(kept);
    if (!scene.uv1.empty()) scene.uv1.resize(kept);
    if (!scene.tangents.empty()) scene.tangents.resize(kept);
    scene.trianglePoses.resize(kept * segments);
    return removed;
}

void addFlatTriangle(Scene& scene, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, uint32_t material) {
    scene.triangles.push_back({v0, v1, v2, material});
    const glm::vec3 normal = glm::normalize(glm::cross(v1 - v0, v2 - v0));
    TriangleShading shading{};
    for (glm::vec3& n : shading.normal) n = normal;
    scene.shading.push_back(shading);
}

void addFlatQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t material) {
    addFlatTriangle(scene, a, b, c, material);
    addFlatTriangle(scene, a, c, d, material);
}

Aabb shapeBounds(uint32_t type, const glm::mat4& toWorld) {
    // Per world axis, the half-extent of the canonical shape under the linear part (column j of toWorld is
    // the image of object axis j): the ellipsoid's exactly, the others' through their box [-1, 1]^3 or, for
    // the round sides, the ellipse of the unit circle in xz plus the height. In double: squared in float, the
    // entries of a shape 1e-20 across vanished (its bounds a point, the shape culled) and those of one 1e20
    // across overflowed.
    const glm::dvec3 center(toWorld[3]);
    glm::dvec3 extent;
    for (int i = 0; i < 3; ++i) {
        const double x = toWorld[0][i], y = toWorld[1][i], z = toWorld[2][i];
        if (type == VKRT_SHAPE_SPHERE)
            extent[i] = std::sqrt(x * x + y * y + z * z);
        else if (type == VKRT_SHAPE_BOX)
            extent[i] = std::abs(x) + std::abs(y) + std::abs(z);
        else
            extent[i] = std::sqrt(x * x + z * z) + std::abs(y);
    }
    // Padded by a few ulps of the magnitudes, so a hit point rounded outwards stays inside.
    extent += 4e-6 * (glm::abs(center) + extent);
    return {glm::vec3(center - extent), glm::vec3(center + extent)};
}

Shape makeShape(uint32_t type, uint32_t material, const glm::dmat4& toWorld) {
    Shape shape{};
    shape.type = type;
    shape.material = material;
    shape.toWorld = glm::mat4(toWorld);
    shape.toObject = glm::inverse(glm::dmat4(shape.toWorld));
    return shape;
}

std::array<uint32_t, 8> truthTable(uint32_t count, const std::function<bool(uint32_t)>& inside) {
    std::array<uint32_t, 8> table{};
    for (uint32_t state = 0; state < (1u << count); ++state) {
        if (inside(state)) table[state >> 5] |= 1u << (state & 31u);
    }
    return table;
}

void addSolid(Scene& scene, const std::vector<Shape>& shapes, const std::array<uint32_t, 8>& inside) {
    Solid solid;
    solid.firstShape = static_cast<uint32_t>(scene.shapes.size());
    solid.shapeCount = static_cast<uint32_t>(shapes.size());
    solid.table = inside;
    for (const Shape& shape : shapes) {
        solid.bounds.grow(shapeBounds(shape.type, shape.toWorld));
        scene.shapes.push_back(shape);
        for (int k = 0; k < scene.motionSegments; ++k) scene.shapePoses.push_back(shape.toWorld);
    }
    scene.solids.push_back(solid);
}

namespace {

// A texture read as colours by one slot (sRGB: base, emissive, specular and sheen colour) and as data by
// another (linear) gets a copy for the data slots (of the same decoded texels, packed apart), since its
// mipmaps are averaged in one space (shading_inputs.cpp's writeTexels): an occlusion map shared with a base
// colour read the colours' encoded means, 0.737 for 0.5.
void separateColourSpaces(Scene& scene) {
    std::vector<bool> colour(scene.textures.size(), false), data(scene.textures.size(), false);
    for (const Material& m : scene.materials) {
        for (const TextureSlot* slot : m.textureSlots()) {
            if (slot->used()) (m.holdsColour(slot) ? colour : data)[slot->texture] = true;
        }
    }
    std::vector<int> dataCopy(scene.textures.size(), -1);
    for (size_t i = 0; i < colour.size(); ++i) {
        const Texture& t = scene.textures[i];
        if (!colour[i] || !data[i] || t.mipmaps == MipmapMode::None || (t.width <= 1 && t.height <= 1))
            continue;
        dataCopy[i] = static_cast<int>(scene.textures.size());
        scene.textures.push_back(scene.textures[i]);
    }
    for (Material& m : scene.materials) {
        for (TextureSlot* slot : m.textureSlots()) {
            if (slot->used() && !m.holdsColour(slot) && dataCopy[slot->texture] >= 0)
                slot->texture = dataCopy[slot->texture];
        }
    }
}

}  // namespace

void finalizeScene(Scene& scene) {
    separateColourSpaces(scene);
    // Triangles added after the last coloured one are white.
    if (!scene.vertexColors.empty()) scene.vertexColors.resize(scene.triangles.size(), kVertexColorWhite);
    if (!scene.uv1.empty()) scene.uv1.resize(scene.triangles.size(), {});
    if (!scene.tangents.empty()) scene.tangents.resize(scene.triangles.size(), {});
    if (const size_t removed = removeDuplicateTriangles(scene); removed > 0) {
        scene.warnings.push_back(std::to_string(removed) + " duplicate triangle(s) removed");
    }
    scene.bounds = Aabb{};
    scene.emissiveTriangles.clear();
    for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        scene.bounds.grow(scene.boundsOf(i));
        if (scene.materials[t.material].emissive()) scene.emissiveTriangles.push_back(i);
    }
    scene.emissiveSpheres.clear();
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        scene.bounds.grow(scene.boundsOf(static_cast<uint32_t>(scene.triangles.size()) + i));
        if (scene.materials[scene.spheres[i].material].emissive()) scene.emissiveSpheres.push_back(i);
    }
    scene.emissiveShapes.clear();
    for (uint32_t i = 0; i < scene.solids.size(); ++i) scene.bounds.grow(scene.solids[i].bounds);
    for (uint32_t i = 0; i < scene.shapes.size(); ++i) {
        if (scene.materials[scene.shapes[i].material].emissive()) scene.emissiveShapes.push_back(i);
    }
}

}  // namespace vkrt
