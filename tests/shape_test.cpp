// Analytic shapes and CSG (VKRT_shape, VKRT_csg; docs/vkrt_shape.md) against answers the test computes on its
// own: the loader's shapes, transforms, materials and truth tables against the file's expression evaluated
// here, and its errors; the canonical shapes' intervals against brute-force point classification, and their
// normals against their implicit functions' gradients; the shape lights' densities against surface areas from
// quadrature; silhouettes of emitting shapes and CSG objects against their analytic areas, and a floor lit by
// a CSG lamp against the lamp's traced solid angle, on the GPU and the CPU; and a CSG lens's focus against
// the thick-lens formula.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "area_light.h"
#include "cpu/closest_hit.h"
#include "cpu/reference_renderer.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/scene_features.h"
#include "optics.h"
#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"
#include "shape_geometry.h"
#include "support/gltf_document.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using nlohmann::json;
using test::bvhFor;

// The GPU tests of this file, named so that `ctest -R Shape` runs them with the rest.
class ShapeGpu : public test::Gpu {};

using Table = std::array<uint32_t, 8>;

// The truth table of a boolean expression over `count` shapes' inside bits: bit s set when the expression
// holds for the state whose set bits are the shapes a point is inside.
Table truthTable(uint32_t count, const std::function<bool(uint32_t)>& inside) {
    Table table{};
    for (uint32_t s = 0; s < (1u << count); ++s) {
        if (inside(s)) table[s >> 5] |= 1u << (s & 31u);
    }
    return table;
}

bool tableBit(const Table& table, uint32_t state) {
    return ((table[state >> 5] >> (state & 31u)) & 1u) != 0u;
}

bool bit(uint32_t state, uint32_t i) {
    return ((state >> i) & 1u) != 0u;
}

const char* shapeName(uint32_t type) {
    switch (type) {
        case VKRT_SHAPE_SPHERE:
            return "sphere";
        case VKRT_SHAPE_BOX:
            return "box";
        case VKRT_SHAPE_CYLINDER:
            return "cylinder";
        default:
            return "cone";
    }
}

constexpr uint32_t kShapeTypes[] = {VKRT_SHAPE_SPHERE, VKRT_SHAPE_BOX, VKRT_SHAPE_CYLINDER, VKRT_SHAPE_CONE};

// Translation, rotation (angle about an axis) and scale, composed as glTF composes a node's TRS.
glm::dmat4 trs(glm::dvec3 translation, double angle, glm::dvec3 axis, glm::dvec3 scale) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translation);
    if (angle != 0.0) m = glm::rotate(m, angle, glm::normalize(axis));
    return glm::scale(m, scale);
}

glm::dvec3 transformPoint(const glm::dmat4& m, glm::dvec3 p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
    std::normal_distribution<double> gauss;
    for (;;) {
        const glm::dvec3 v(gauss(rng), gauss(rng), gauss(rng));
        const double length = glm::length(v);
        if (length > 1e-6) return v / length;
    }
}

// A point well inside each canonical shape, from which every direction leaves it once.
glm::dvec3 innerPoint(uint32_t type) {
    return type == VKRT_SHAPE_CONE ? glm::dvec3(0.0, -0.5, 0.0) : glm::dvec3(0.0);
}

// ---------------------------------------------------------------------------------------------------------
// Loading

// A glTF document of the given nodes (scene roots `roots`) with two materials: "matte" and an emitting
// "lamp".
json documentOf(const json& nodes, const json& roots) {
    return json{{"asset", {{"version", "2.0"}}},
                {"extensionsUsed", {"VKRT_shape", "VKRT_csg"}},
                {"extensionsRequired", {"VKRT_shape", "VKRT_csg"}},
                {"scene", 0},
                {"scenes", {{{"nodes", roots}}}},
                {"materials", {{{"name", "matte"}}, {{"name", "lamp"}, {"emissiveFactor", {1.0, 1.0, 1.0}}}}},
                {"nodes", nodes}};
}

json shapeExtension(const char* shape, int material = -1) {
    json e = {{"shape", shape}};
    if (material >= 0) e["material"] = material;
    return json{{"VKRT_shape", e}};
}

json csgExtension(const char* operation) {
    return json{{"VKRT_csg", {{"operation", operation}}}};
}

std::filesystem::path writeDocument(const std::filesystem::path& folder, const std::string& name,
                                    const json& document) {
    const std::filesystem::path file = folder / (name + ".gltf");
    test::writeText(file, document.dump());
    return file;
}

// glTF's quaternion [x, y, z, w] of a rotation by `angle` about unit `axis`.
json quaternion(double angle, glm::dvec3 axis) {
    axis = glm::normalize(axis);
    const double s = std::sin(0.5 * angle);
    return json{s * axis.x, s * axis.y, s * axis.z, std::cos(0.5 * angle)};
}

TEST(ShapeLoader, ShapesTransformsMaterialsAndTruthTablesFollowTheFile) {
    // Two shapes alone (a box under a non-uniform scale and a rotation; a sphere under a sheared `matrix`,
    // with glTF's default material) and a CSG object, placed by its own transform:
    //   carved = difference(union(block, intersection(tube, spike)), bite)
    // with a box, a cylinder, a cone and a sphere, each with its own transform.
    const glm::dvec3 slabAxis(1.0, 2.0, 2.0), pointyAxis(0.0, 0.0, 1.0);
    const double slabAngle = 0.8, pointyAngle = 0.4;
    // Column-major, as glTF's `matrix`: x leans with y (shear), z with x and y, then a translation.
    const std::array<double, 16> shear = {0.6, 0.0,  0.0, 0.0, 0.3, 0.5,  0.0, 0.0,
                                          0.1, -0.2, 0.4, 0.0, 0.0, -1.0, 2.0, 1.0};
    json nodes = json::array();
    nodes.push_back({{"name", "slab"},
                     {"translation", {1.0, 2.0, 3.0}},
                     {"rotation", quaternion(slabAngle, slabAxis)},
                     {"scale", {0.5, 0.3, 0.2}},
                     {"extensions", shapeExtension("box", 0)}});
    nodes.push_back({{"name", "sheared ball"}, {"matrix", shear}, {"extensions", shapeExtension("sphere")}});
    nodes.push_back({{"name", "carved"},
                     {"translation", {-2.0, 0.0, 0.5}},
                     {"scale", {1.5, 1.5, 1.5}},
                     {"children", {3, 7}},
                     {"extensions", csgExtension("difference")}});
    nodes.push_back({{"name", "union"}, {"children", {4, 5}}, {"extensions", csgExtension("union")}});
    nodes.push_back({{"name", "block"},
                     {"translation", {0.3, 0.0, 0.0}},
                     {"scale", {1.0, 0.5, 0.5}},
                     {"extensions", shapeExtension("box", 1)}});
    nodes.push_back({{"name", "pointy"},
                     {"rotation", quaternion(pointyAngle, pointyAxis)},
                     {"children", {6, 8}},
                     {"extensions", csgExtension("intersection")}});
    nodes.push_back(
        {{"name", "tube"}, {"scale", {0.4, 1.0, 0.4}}, {"extensions", shapeExtension("cylinder", 0)}});
    nodes.push_back({{"name", "bite"},
                     {"translation", {0.8, 0.3, 0.0}},
                     {"scale", {0.6, 0.6, 0.6}},
                     {"extensions", shapeExtension("sphere", 1)}});
    nodes.push_back(
        {{"name", "spike"}, {"translation", {0.0, 0.5, 0.0}}, {"extensions", shapeExtension("cone")}});
    const auto file = writeDocument(test::temporaryFolder(), "shapes", documentOf(nodes, {0, 1, 2}));
    const Scene scene = loadGltf(file.string());
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();

    // Three solids, six shapes: the operands are not solids of their own, nor are the inner VKRT_csg nodes.
    ASSERT_EQ(scene.solids.size(), 3u);
    ASSERT_EQ(scene.shapes.size(), 6u);
    EXPECT_TRUE(scene.triangles.empty());
    EXPECT_TRUE(scene.spheres.empty());
    EXPECT_EQ(scene.primitiveCount(), 3u);
    uint32_t shapesInSolids = 0;
    for (const Solid& solid : scene.solids) {
        ASSERT_LE(solid.firstShape + solid.shapeCount, scene.shapes.size());
        shapesInSolids += solid.shapeCount;
    }
    EXPECT_EQ(shapesInSolids, 6u);

    // The expected object-to-world maps, composed here from the nodes' TRS (world = stored + scene.origin).
    const glm::dmat4 slab = trs({1.0, 2.0, 3.0}, slabAngle, slabAxis, {0.5, 0.3, 0.2});
    glm::dmat4 ball;
    for (int i = 0; i < 16; ++i) ball[i / 4][i % 4] = shear[i];
    const glm::dmat4 carved = trs({-2.0, 0.0, 0.5}, 0.0, {0, 0, 1}, glm::dvec3(1.5));
    const glm::dmat4 block = carved * trs({0.3, 0.0, 0.0}, 0.0, {0, 0, 1}, {1.0, 0.5, 0.5});
    const glm::dmat4 pointy = carved * trs({0, 0, 0}, pointyAngle, pointyAxis, glm::dvec3(1.0));
    const glm::dmat4 tube = pointy * trs({0, 0, 0}, 0.0, {0, 0, 1}, {0.4, 1.0, 0.4});
    const glm::dmat4 spike = pointy * trs({0.0, 0.5, 0.0}, 0.0, {0, 0, 1}, glm::dvec3(1.0));
    const glm::dmat4 bite = carved * trs({0.8, 0.3, 0.0}, 0.0, {0, 0, 1}, glm::dvec3(0.6));
    auto expectPlaced = [&](uint32_t shape, const glm::dmat4& expected, const char* name) {
        glm::dmat4 world(scene.shapes[shape].toWorld);
        world[3] += glm::dvec4(scene.origin, 0.0);
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 3; ++r)
                EXPECT_NEAR(world[c][r], expected[c][r], 1e-6) << name << " [" << c << "][" << r << "]";
        }
        // toObject is its inverse (stored coordinates).
        const glm::dmat4 product = scene.shapes[shape].toObject * glm::dmat4(scene.shapes[shape].toWorld);
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) EXPECT_NEAR(product[c][r], c == r ? 1.0 : 0.0, 1e-9) << name;
        }
    };
    const uint32_t defaultMaterial = static_cast<uint32_t>(scene.materials.size()) - 1;
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[defaultMaterial].name, "default");

    // The lone shapes, found by type (the loader's order of solids is its own).
    const Solid* slabSolid = nullptr;
    const Solid* ballSolid = nullptr;
    const Solid* carvedSolid = nullptr;
    for (const Solid& solid : scene.solids) {
        if (solid.shapeCount == 4) carvedSolid = &solid;
        if (solid.shapeCount == 1 && scene.shapes[solid.firstShape].type == VKRT_SHAPE_BOX)
            slabSolid = &solid;
        if (solid.shapeCount == 1 && scene.shapes[solid.firstShape].type == VKRT_SHAPE_SPHERE)
            ballSolid = &solid;
    }
    ASSERT_TRUE(slabSolid && ballSolid && carvedSolid);
    expectPlaced(slabSolid->firstShape, slab, "slab");
    expectPlaced(ballSolid->firstShape, ball, "sheared ball");
    EXPECT_EQ(scene.shapes[slabSolid->firstShape].material, 0u);
    EXPECT_EQ(scene.shapes[ballSolid->firstShape].material, defaultMaterial);
    // A lone shape's table is "inside": state 1 only.
    for (const Solid* solid : {slabSolid, ballSolid})
        EXPECT_EQ(solid->table, truthTable(1, [](uint32_t s) { return s == 1u; }));

    // The CSG object's shapes, by type: each with its own transform and material.
    int role[4] = {-1, -1, -1, -1};  // block, tube, spike, bite: the shape's place in the object
    for (uint32_t k = 0; k < 4; ++k) {
        const uint32_t type = scene.shapes[carvedSolid->firstShape + k].type;
        const int r = type == VKRT_SHAPE_BOX        ? 0
                      : type == VKRT_SHAPE_CYLINDER ? 1
                      : type == VKRT_SHAPE_CONE     ? 2
                                                    : 3;
        ASSERT_EQ(role[r], -1) << "two shapes of type " << shapeName(type);
        role[r] = static_cast<int>(k);
    }
    const uint32_t first = carvedSolid->firstShape;
    expectPlaced(first + role[0], block, "block");
    expectPlaced(first + role[1], tube, "tube");
    expectPlaced(first + role[2], spike, "spike");
    expectPlaced(first + role[3], bite, "bite");
    EXPECT_EQ(scene.shapes[first + role[0]].material, 1u);
    EXPECT_EQ(scene.shapes[first + role[1]].material, 0u);
    EXPECT_EQ(scene.shapes[first + role[2]].material, defaultMaterial);
    EXPECT_EQ(scene.shapes[first + role[3]].material, 1u);
    const uint32_t carvedPrimitive =
        scene.firstSolid() + static_cast<uint32_t>(carvedSolid - scene.solids.data());
    EXPECT_TRUE(scene.isSolid(carvedPrimitive));
    EXPECT_EQ(scene.materialOf(carvedPrimitive), scene.shapes[first].material);
    // The lamp material's shapes, and only they, are lights.
    std::vector<uint32_t> lamps = {first + role[0], first + role[3]};
    std::sort(lamps.begin(), lamps.end());
    std::vector<uint32_t> emissive = scene.emissiveShapes;
    std::sort(emissive.begin(), emissive.end());
    EXPECT_EQ(emissive, lamps);

    // The table is the expression, evaluated here for every state of the scene's bit order.
    const Table expected = truthTable(4, [&](uint32_t s) {
        const bool inBlock = bit(s, role[0]), inTube = bit(s, role[1]), inSpike = bit(s, role[2]),
                   inBite = bit(s, role[3]);
        return (inBlock || (inTube && inSpike)) && !inBite;
    });
    for (uint32_t s = 0; s < 16; ++s)
        EXPECT_EQ(tableBit(carvedSolid->table, s), tableBit(expected, s)) << "state " << s;
    for (uint32_t s = 16; s < 256; ++s) EXPECT_FALSE(tableBit(carvedSolid->table, s)) << "state " << s;

    // Bounds: every point of a solid (sampled on its shapes' surfaces, kept where the solid holds it) lies in
    // its bounds and the scene's.
    std::mt19937_64 rng(7);
    for (const Solid& solid : scene.solids) {
        int checked = 0;
        for (uint32_t k = 0; k < solid.shapeCount; ++k) {
            const Shape& shape = scene.shapes[solid.firstShape + k];
            for (int j = 0; j < 2000; ++j) {
                const glm::dvec3 from = innerPoint(shape.type), direction = randomUnit(rng);
                double tIn, tOut;
                uint32_t faceIn, faceOut;
                ASSERT_TRUE(shading::shapeInterval(shape.type, from, direction, tIn, tOut, faceIn, faceOut));
                const glm::dvec3 world = transformPoint(glm::dmat4(shape.toWorld), from + tOut * direction);
                uint32_t state = 1u << k;
                for (uint32_t other = 0; other < solid.shapeCount; ++other) {
                    const Shape& o = scene.shapes[solid.firstShape + other];
                    if (other != k && shading::shapeContains(o.type, transformPoint(o.toObject, world)))
                        state |= 1u << other;
                }
                if (!tableBit(solid.table, state)) continue;
                ++checked;
                const double slack = 1e-5 * (1.0 + glm::length(world));
                for (const Aabb* bounds : {&solid.bounds, &scene.bounds}) {
                    for (int a = 0; a < 3; ++a) {
                        ASSERT_GE(world[a], bounds->min[a] - slack) << "axis " << a;
                        ASSERT_LE(world[a], bounds->max[a] + slack) << "axis " << a;
                    }
                }
            }
        }
        EXPECT_GT(checked, 1000);
    }
    // The lone shapes' bounds are tight: the box's from its corners, the ellipsoid's from its rows' lengths.
    auto expectTight = [&](const Solid& solid, const glm::dvec3& halfExtent, const glm::dvec3& center,
                           const char* name) {
        for (int a = 0; a < 3; ++a) {
            const double storedCenter = center[a] - scene.origin[a];
            EXPECT_NEAR(solid.bounds.min[a], storedCenter - halfExtent[a], 1e-4) << name << " axis " << a;
            EXPECT_NEAR(solid.bounds.max[a], storedCenter + halfExtent[a], 1e-4) << name << " axis " << a;
        }
    };
    glm::dvec3 slabExtent(0.0), ballExtent(0.0);
    for (int a = 0; a < 3; ++a) {
        for (int j = 0; j < 3; ++j) {
            slabExtent[a] += std::abs(slab[j][a]);
            ballExtent[a] += ball[j][a] * ball[j][a];
        }
        ballExtent[a] = std::sqrt(ballExtent[a]);
    }
    expectTight(*slabSolid, slabExtent, glm::dvec3(slab[3]), "slab");
    expectTight(*ballSolid, ballExtent, glm::dvec3(ball[3]), "sheared ball");
}

// Two boxes moving through each other over the shutter meet only between its ends: the intersection's bounds
// are those of what each box sweeps, not the pose-by-pose intersections (empty at both ends: the solid was
// left out as empty, and one that met a little at the ends was cut to that).
TEST(ShapeLoader, MovingIntersectionIsBoundedByWhatItsOperandsSweep) {
    const auto folder = test::temporaryFolder();
    const std::vector<float> keys = {0.0f, 1.0f, -1.0f, 0.0f, 0.0f,  1.0f, 0.0f,
                                     0.0f, 1.0f, 0.0f,  0.0f, -1.0f, 0.0f, 0.0f};
    test::writeText(folder / "keys.bin",
                    std::string(reinterpret_cast<const char*>(keys.data()), keys.size() * 4));
    json nodes = json::array();
    nodes.push_back(
        {{"name", "meeting"}, {"children", {1, 2}}, {"extensions", csgExtension("intersection")}});
    nodes.push_back({{"name", "a"}, {"scale", {0.5, 0.5, 0.5}}, {"extensions", shapeExtension("box", 0)}});
    nodes.push_back({{"name", "b"}, {"scale", {0.5, 0.5, 0.5}}, {"extensions", shapeExtension("box", 0)}});
    json document = documentOf(nodes, {0});
    document["scenes"][0]["extras"] = {{"shutter", {0.0, 1.0}}};
    document["buffers"] = {{{"uri", "keys.bin"}, {"byteLength", 56}}};
    document["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 8}},
                               {{"buffer", 0}, {"byteOffset", 8}, {"byteLength", 24}},
                               {{"buffer", 0}, {"byteOffset", 32}, {"byteLength", 24}}};
    document["accessors"] = {{{"bufferView", 0},
                              {"componentType", 5126},
                              {"count", 2},
                              {"type", "SCALAR"},
                              {"min", {0.0}},
                              {"max", {1.0}}},
                             {{"bufferView", 1}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}},
                             {{"bufferView", 2}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}}};
    document["animations"] = {{{"samplers", {{{"input", 0}, {"output", 1}}, {{"input", 0}, {"output", 2}}}},
                               {"channels",
                                {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                                 {{"sampler", 1}, {"target", {{"node", 2}, {"path", "translation"}}}}}}}};
    const Scene scene = loadGltf(writeDocument(folder, "meeting", document).string());
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.solids.size(), 1u);
    // Mid-shutter both boxes are at the origin: [-0.5, 0.5]^3 is the intersection then.
    const Aabb& b = scene.solids[0].bounds;
    const glm::dvec3 lo = glm::dvec3(b.min) + scene.origin, hi = glm::dvec3(b.max) + scene.origin;
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_LE(lo[axis], -0.5 + 1e-6) << axis;
        EXPECT_GE(hi[axis], 0.5 - 1e-6) << axis;
    }
}

TEST(ShapeLoader, EightShapesLoadAndTheirTableIsTheUnion) {
    // The limit itself: eight spheres in one union, a table of all 256 states.
    json nodes = json::array();
    nodes.push_back(
        {{"name", "eight"}, {"children", {1, 2, 3, 4, 5, 6, 7, 8}}, {"extensions", csgExtension("union")}});
    for (int i = 0; i < 8; ++i) {
        nodes.push_back({{"translation", {0.5 * i, 0.0, 0.0}},
                         {"scale", {0.3, 0.3, 0.3}},
                         {"extensions", shapeExtension("sphere", 0)}});
    }
    const auto file = writeDocument(test::temporaryFolder(), "eight", documentOf(nodes, {0}));
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.solids.size(), 1u);
    ASSERT_EQ(scene.solids[0].shapeCount, 8u);
    EXPECT_EQ(scene.solids[0].table, truthTable(8, [](uint32_t s) { return s != 0u; }));
}

TEST(ShapeLoader, LongThinShapesAreNotSingular) {
    // A rod 2e4 long and 2e-4 thick: its map is orthogonal, its inverse exact. (Its determinant, 1e-4, was
    // compared with the largest scale cubed, and rods of aspect 1e6 were refused as singular.)
    const json nodes = {
        {{"name", "rod"}, {"scale", {1e-4, 1e-4, 1e4}}, {"extensions", shapeExtension("cylinder")}}};
    const auto file = writeDocument(test::temporaryFolder(), "rod", documentOf(nodes, {0}));
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.shapes.size(), 1u);
    const glm::dmat4 roundTrip = scene.shapes[0].toObject * glm::dmat4(scene.shapes[0].toWorld);
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(roundTrip[c][r], c == r ? 1.0 : 0.0, 1e-12) << c << r;
    }
}

// A data-URI buffer with one triangle (3 float positions, then 3 uint16 indices) and its mesh.
void addTriangleMesh(json& document) {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t indices[4] = {0, 1, 2, 0};
    std::vector<uint8_t> bytes(44);
    std::memcpy(bytes.data(), positions, 36);
    std::memcpy(bytes.data() + 36, indices, 8);
    const std::string encoded = test::base64(bytes);
    document["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}};
    document["accessors"] = {{{"bufferView", 0},
                              {"componentType", 5126},
                              {"count", 3},
                              {"type", "VEC3"},
                              {"min", {0, 0, 0}},
                              {"max", {1, 1, 0}}},
                             {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}};
    document["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                               {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}};
    document["buffers"] = {
        {{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + encoded}}};
}

struct BadShapeFile {
    const char* name;
    json document;
    std::vector<const char*> phrases;  // what the one-line error must name
};

std::vector<BadShapeFile> badShapeFiles() {
    std::vector<BadShapeFile> files;
    files.push_back({"unknown shape",
                     documentOf({{{"name", "doughnut"}, {"extensions", shapeExtension("torus")}}}, {0}),
                     {"VKRT_shape", "torus"}});
    files.push_back(
        {"singular transform",
         documentOf(
             {{{"name", "flat box"}, {"scale", {1.0, 0.0, 1.0}}, {"extensions", shapeExtension("box")}}},
             {0}),
         {"flat box", "singular"}});
    files.push_back(  // sheared until its axes lie within 1e-7 of a plane (column-major: x, then y = x + 1e-7
                      // y)
        {"sheared flat",
         documentOf(
             {{{"name", "sheared box"},
               {"matrix", {1.0, 0.0, 0.0, 0.0, 1.0, 1e-7, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0}},
               {"extensions", shapeExtension("box")}}},
             {0}),
         {"sheared box", "singular"}});
    files.push_back(  // a float map of entries 1e-39 holds a few bits each
        {"vanishing scale",
         documentOf(
             {{{"name", "speck"}, {"scale", {1e-39, 1e-39, 1e-39}}, {"extensions", shapeExtension("box")}}},
             {0}),
         {"speck", "below 1e-30"}});
    {
        json document =
            documentOf({{{"name", "pair"}, {"children", {1, 2}}, {"extensions", csgExtension("union")}},
                        {{"name", "ball"}, {"extensions", shapeExtension("sphere")}},
                        {{"name", "meshy"}, {"mesh", 0}, {"extensions", shapeExtension("box")}}},
                       {0});
        addTriangleMesh(document);
        files.push_back({"operand with a mesh", document, {"meshy", "mesh"}});
    }
    files.push_back(
        {"operand without an extension",
         documentOf({{{"name", "pair"}, {"children", {1, 2}}, {"extensions", csgExtension("union")}},
                     {{"name", "ball"}, {"extensions", shapeExtension("sphere")}},
                     {{"name", "plain"}, {"translation", {1.0, 0.0, 0.0}}}},
                    {0}),
         {"plain", "without VKRT_shape or VKRT_csg"}});
    files.push_back({"csg without children",
                     documentOf({{{"name", "hollow"}, {"extensions", csgExtension("intersection")}}}, {0}),
                     {"hollow", "no operands"}});
    {
        json both = shapeExtension("box");
        both["VKRT_csg"] = {{"operation", "union"}};
        files.push_back({"both extensions",
                         documentOf({{{"name", "twofold"}, {"children", {1}}, {"extensions", both}},
                                     {{"name", "ball"}, {"extensions", shapeExtension("sphere")}}},
                                    {0}),
                         {"twofold", "both VKRT_shape and VKRT_csg"}});
    }
    {
        // Nine shapes: a union of a sphere and a nested union of eight.
        json nodes = json::array();
        nodes.push_back({{"name", "crowd"}, {"children", {1, 2}}, {"extensions", csgExtension("union")}});
        nodes.push_back({{"extensions", shapeExtension("sphere")}});
        nodes.push_back({{"children", {3, 4, 5, 6, 7, 8, 9, 10}}, {"extensions", csgExtension("union")}});
        for (int i = 0; i < 8; ++i) {
            nodes.push_back({{"translation", {0.5 * i, 0.0, 0.0}}, {"extensions", shapeExtension("box")}});
        }
        files.push_back({"nine shapes", documentOf(nodes, {0}), {"crowd", "the limit is 8"}});
    }
    return files;
}

TEST(ShapeLoader, BadShapesAndCsgTreesFailWithOneLineNamingTheProblem) {
    const auto folder = test::temporaryFolder();
    for (const BadShapeFile& bad : badShapeFiles()) {
        SCOPED_TRACE(bad.name);
        std::string name = bad.name;
        std::replace(name.begin(), name.end(), ' ', '-');
        const auto file = writeDocument(folder, name, bad.document);
        try {
            loadGltf(file.string());
            ADD_FAILURE() << "loaded without error";
        } catch (const SceneError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            EXPECT_NE(message.find(file.string()), std::string::npos) << "names the file: " << message;
            for (const char* phrase : bad.phrases)
                EXPECT_NE(message.find(phrase), std::string::npos) << phrase << ": " << message;
        }
    }
}

TEST(ShapeLoader, CommandExitsWithCodeTwoOnBadShapes) {
    const auto folder = test::temporaryFolder();
    for (const BadShapeFile& bad : badShapeFiles()) {
        SCOPED_TRACE(bad.name);
        const auto file = writeDocument(folder, "bad", bad.document);
        const auto output = folder / "out.png";
        const test::CommandResult result = test::runVkrt("--scene '" + file.string() + "' --out '" +
                                                         output.string() + "' --width 8 --height 8");
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_NE(result.output.find("vkrt: error: "), std::string::npos) << result.output;
        EXPECT_NE(result.output.find(bad.phrases.back()), std::string::npos) << result.output;
        EXPECT_FALSE(std::filesystem::exists(output));
    }
}

// ---------------------------------------------------------------------------------------------------------
// Geometry in double precision

// Whether p, on face `face` of shape `type`, is within `margin` of another face (an edge, a rim, the apex),
// where the face it lies nearest to is a matter of rounding.
bool nearEdge(uint32_t type, uint32_t face, const glm::dvec3& p, double margin) {
    if (type == VKRT_SHAPE_SPHERE) return false;
    if (type == VKRT_SHAPE_BOX) {
        const int axis = static_cast<int>(face / 2);
        return std::abs(p[(axis + 1) % 3]) > 1.0 - margin || std::abs(p[(axis + 2) % 3]) > 1.0 - margin;
    }
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    if (face != VKRT_FACE_SIDE) return rho > 1.0 - margin;
    return p.y < -1.0 + margin || p.y > 1.0 - margin;
}

// The outward unit normal of face `face` at p, from the gradient of the face's own implicit function: |p|^2 -
// 1 (sphere), +-p_axis - 1 (box), x^2 + z^2 - 1 (round side), -+y - 1 (caps), sqrt(x^2 + z^2) - (1 - y) / 2
// (the cone's side).
glm::dvec3 implicitNormal(uint32_t type, uint32_t face, const glm::dvec3& p) {
    if (type == VKRT_SHAPE_SPHERE) return glm::normalize(p);
    if (type == VKRT_SHAPE_BOX) {
        glm::dvec3 n(0.0);
        n[face / 2] = face % 2 == 1 ? 1.0 : -1.0;
        return n;
    }
    if (face == VKRT_FACE_BOTTOM) return {0.0, -1.0, 0.0};
    if (face == VKRT_FACE_TOP) return {0.0, 1.0, 0.0};
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    if (type == VKRT_SHAPE_CYLINDER) return {p.x / rho, 0.0, p.z / rho};
    return glm::normalize(glm::dvec3(p.x / rho, 0.5, p.z / rho));
}

// Checks one ray against canonical shape `type`: points sampled densely along it (`samples` over t in
// [tLo, tHi], which must cover the shape) are inside by shapeContains exactly where shapeInterval says, but
// for those within 1e-9 of an end; a miss has none inside. At each end the snapped point is on the surface:
// inside just behind it along the face's normal and outside just in front, the normal (the face's implicit
// function's gradient) against the ray where it enters and along it where it leaves, and the face the one
// shapeFaceAt finds (away from edges). Returns whether it hit; counts and reports (the first few) wrong
// samples.
bool checkRay(uint32_t type, const glm::dvec3& origin, const glm::dvec3& direction, double tLo, double tHi,
              int samples, const std::string& label, int& wrongSamples) {
    double tIn = 0.0, tOut = 0.0;
    uint32_t faceIn = 0, faceOut = 0;
    const bool hit = shading::shapeInterval(type, origin, direction, tIn, tOut, faceIn, faceOut);
    auto inside = [&](double t) { return shading::shapeContains(type, origin + t * direction); };
    for (int k = 0; k < samples; ++k) {
        const double t = tLo + (k + 0.5) * (tHi - tLo) / samples;
        if (hit && (std::abs(t - tIn) < 1e-9 || std::abs(t - tOut) < 1e-9)) continue;
        const bool expected = hit && t > tIn && t < tOut;
        if (inside(t) != expected && ++wrongSamples <= 5) {
            ADD_FAILURE() << label << " at t " << t << ": shapeContains says " << inside(t)
                          << ", the interval " << (hit ? "hit" : "missed") << " [" << tIn << ", " << tOut
                          << "]";
        }
    }
    if (!hit) return false;
    EXPECT_TRUE(std::isfinite(tIn) && std::isfinite(tOut)) << label;
    EXPECT_LE(tIn, tOut) << label;
    EXPECT_GT(tIn, tLo) << label;
    EXPECT_LT(tOut, tHi) << label;
    if (tOut - tIn > 1e-9) {
        EXPECT_TRUE(inside(0.5 * (tIn + tOut))) << label;
    }
    EXPECT_FALSE(inside(tIn - 1e-6)) << label;
    EXPECT_FALSE(inside(tOut + 1e-6)) << label;
    for (const bool entering : {true, false}) {
        const double t = entering ? tIn : tOut;
        const uint32_t face = entering ? faceIn : faceOut;
        const glm::dvec3 p = origin + t * direction;
        const glm::dvec3 snapped = shading::shapeSnap(type, face, p);
        const glm::dvec3 n = shading::shapeNormal(type, face, snapped);
        // Said only on failure (GoogleTest evaluates a message only then).
        auto where = [&] {
            std::ostringstream at;
            at << label << (entering ? " entry" : " exit") << " on face " << face << " at t " << t << ", ("
               << snapped.x << ", " << snapped.y << ", " << snapped.z << "), normal (" << n.x << ", " << n.y
               << ", " << n.z << "), interval [" << tIn << ", " << tOut << "]";
            return at.str();
        };
        EXPECT_LT(glm::length(snapped - p), 1e-9) << where();
        EXPECT_NEAR(glm::length(n), 1.0, 1e-12) << where();
        // On an edge (the cone's rim and apex among them) the point lies on two faces and the steps along
        // one's normal need not stay on its side of the other.
        if (nearEdge(type, face, snapped, 1e-6)) continue;
        EXPECT_TRUE(shading::shapeContains(type, snapped - 1e-7 * n)) << where();
        EXPECT_FALSE(shading::shapeContains(type, snapped + 1e-7 * n)) << where();
        const double along = glm::dot(n, direction);
        EXPECT_TRUE(entering ? along <= 1e-12 : along >= -1e-12)
            << where() << ": normal . direction " << along;
        EXPECT_EQ(shading::shapeFaceAt(type, snapped), face) << where();
        EXPECT_LT(glm::length(n - implicitNormal(type, face, snapped)), 1e-12) << where();
    }
    return true;
}

TEST(ShapeGeometry, IntervalsAgreeWithPointClassificationAndEndOnTheSurface) {
    // Per shape, 2,000 random rays from a sphere of radius 3 towards random points of [-1.5, 1.5]^3, sampled
    // over t in [1.2, 4.8] (the shapes lie within sqrt 3 of the centre); then the special cases, exactly:
    // rays parallel to the axes, to face diagonals and to the cone's rulings (where its quadric's leading
    // coefficient is exactly 0), from every point of a grid of step 0.5 over [-1.5, 1.5]^3 (on the faces'
    // planes, the axis and the apex's height, inside and outside).
    for (const uint32_t type : kShapeTypes) {
        SCOPED_TRACE(shapeName(type));
        std::mt19937_64 rng(1000 + type);
        std::uniform_real_distribution<double> uniform(-1.5, 1.5);
        int hits = 0, wrongSamples = 0;
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 origin = 3.0 * randomUnit(rng);
            const glm::dvec3 target(uniform(rng), uniform(rng), uniform(rng));
            hits += checkRay(type, origin, glm::normalize(target - origin), 1.2, 4.8, 8000,
                             "ray " + std::to_string(i), wrongSamples);
        }
        EXPECT_GT(hits, 300);
        const glm::dvec3 directions[] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {-1, 0, 0},   {0, -1, 0},
                                         {0, 0, -1}, {1, 1, 0},  {0, 1, -1}, {1, 0, 1},    {1, -2, 0},
                                         {0, -2, 1}, {-1, 2, 0}, {0, 2, -1}, {0.5, -1, 0}, {1, 1, 1}};
        int specialHits = 0;
        for (const glm::dvec3& direction : directions) {
            const double reach = 4.5 / glm::length(direction);
            for (int gx = 0; gx < 7; ++gx) {
                for (int gy = 0; gy < 7; ++gy) {
                    for (int gz = 0; gz < 7; ++gz) {
                        const glm::dvec3 origin(-1.5 + 0.5 * gx, -1.5 + 0.5 * gy, -1.5 + 0.5 * gz);
                        std::ostringstream label;
                        label << "ray from (" << origin.x << ", " << origin.y << ", " << origin.z
                              << ") along (" << direction.x << ", " << direction.y << ", " << direction.z
                              << ")";
                        specialHits +=
                            checkRay(type, origin, direction, -reach, reach, 3000, label.str(), wrongSamples);
                    }
                }
            }
        }
        EXPECT_GT(specialHits, 300);
        EXPECT_EQ(wrongSamples, 0);
        std::printf("%s: %d of 2000 random rays and %d of %zu special rays hit\n", shapeName(type), hits,
                    specialHits, std::size(directions) * 343);
    }
}

// An affine map with shear and a mirror (a negative determinant), translated off the origin.
glm::dmat4 shearedMirror() {
    const glm::dmat4 m(glm::dvec4(0.8, 0.1, -0.3, 0.0), glm::dvec4(0.4, 0.6, 0.2, 0.0),
                       glm::dvec4(-0.2, 0.3, -0.9, 0.0), glm::dvec4(0.5, -1.0, 2.0, 1.0));
    EXPECT_LT(glm::determinant(m), 0.0);
    return m;
}

TEST(ShapeGeometry, PlacedShapesHaveNormalsByTheInverseTranspose) {
    // Each shape under an affine map with shear and a mirror: shapePoint's world normal is a unit vector
    // perpendicular to the images of two object-space tangents at the point, on the side of the image of
    // the object-space outward normal (so outward, also mirrored); reversed when `flip`; its point is the
    // ray's point at t.
    const glm::dmat4 toWorld = shearedMirror();
    const glm::dmat4 toObject = glm::inverse(toWorld);
    const shading::AffineRows rows = shading::affineRows(toObject);
    const glm::dvec3 center(toWorld[3]);
    for (const uint32_t type : kShapeTypes) {
        SCOPED_TRACE(shapeName(type));
        std::mt19937_64 rng(2000 + type);
        int hits = 0;
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 origin = center + 4.0 * randomUnit(rng);
            const glm::dvec3 target = center + 0.8 * randomUnit(rng);
            const glm::dvec3 direction = glm::normalize(target - origin);
            const glm::dvec3 o = transformPoint(toObject, origin), d(toObject * glm::dvec4(direction, 0.0));
            double tIn, tOut;
            uint32_t faceIn, faceOut;
            if (!shading::shapeInterval(type, o, d, tIn, tOut, faceIn, faceOut)) continue;
            ++hits;
            for (const bool entering : {true, false}) {
                const double t = entering ? tIn : tOut;
                const uint32_t face = entering ? faceIn : faceOut;
                const shading::ShapePoint p =
                    shading::shapePoint(type, face, false, rows, origin, direction, t);
                const shading::ShapePoint flipped =
                    shading::shapePoint(type, face, true, rows, origin, direction, t);
                const glm::dvec3 objectNormal = shading::shapeNormal(type, face, p.local);
                glm::dvec3 tangent1 = glm::cross(objectNormal, glm::dvec3(0.3, 0.5, 0.8));
                tangent1 = glm::normalize(tangent1);
                const glm::dvec3 tangent2 = glm::cross(objectNormal, tangent1);
                const glm::dvec3 worldTangent1 =
                    glm::normalize(glm::dvec3(toWorld * glm::dvec4(tangent1, 0.0)));
                const glm::dvec3 worldTangent2 =
                    glm::normalize(glm::dvec3(toWorld * glm::dvec4(tangent2, 0.0)));
                const glm::dvec3 worldOutward(toWorld * glm::dvec4(objectNormal, 0.0));
                EXPECT_NEAR(glm::length(p.normal), 1.0, 1e-12);
                EXPECT_NEAR(glm::dot(p.normal, worldTangent1), 0.0, 1e-9) << "ray " << i;
                EXPECT_NEAR(glm::dot(p.normal, worldTangent2), 0.0, 1e-9) << "ray " << i;
                EXPECT_GT(glm::dot(p.normal, worldOutward), 0.0) << "ray " << i;
                EXPECT_LT(glm::length(flipped.normal + p.normal), 1e-15) << "ray " << i;
                const glm::dvec3 world = transformPoint(toWorld, p.local);
                EXPECT_LT(glm::length(world - (origin + t * direction)), 1e-9) << "ray " << i;
                // Entering, the outward normal faces the ray; leaving, it does not.
                const double along = glm::dot(p.normal, direction);
                EXPECT_TRUE(entering ? along <= 1e-12 : along >= -1e-12) << "ray " << i;
            }
        }
        EXPECT_GT(hits, 500);
    }
}

// ---------------------------------------------------------------------------------------------------------
// Light sampling

// The integral of f over the world surface of canonical shape `type` placed by linear map `linear` (the
// translation is f's business), by midpoint quadrature over each part's parametrisation with the area
// element from the mapped tangents: |L dp/da x L dp/db| da db.
double surfaceIntegral(uint32_t type, const glm::dmat3& linear, const std::function<double(glm::dvec3)>& f,
                       int n = 1200) {
    double sum = 0.0;
    const double pi = M_PI;
    auto element = [&](glm::dvec3 ta, glm::dvec3 tb) {
        return glm::length(glm::cross(linear * ta, linear * tb));
    };
    auto flatFace = [&](glm::dvec3 corner, glm::dvec3 edgeA, glm::dvec3 edgeB) {
        // corner + a edgeA + b edgeB, a and b in [0, 1]
        const double area = element(edgeA, edgeB) / (double(n) * n);
        double s = 0.0;
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j)
                s += f(linear * (corner + (i + 0.5) / n * edgeA + (j + 0.5) / n * edgeB));
        }
        return s * area;
    };
    auto disk = [&](double y) {
        // (r sin phi, y, r cos phi): dp/dr = (sin, 0, cos), dp/dphi = r (cos, 0, -sin)
        double s = 0.0;
        for (int i = 0; i < n; ++i) {
            const double r = (i + 0.5) / n;
            for (int j = 0; j < n; ++j) {
                const double phi = 2.0 * pi * (j + 0.5) / n;
                const glm::dvec3 p(r * std::sin(phi), y, r * std::cos(phi));
                s += f(linear * p) * r *
                     element({std::sin(phi), 0, std::cos(phi)}, {std::cos(phi), 0, -std::sin(phi)});
            }
        }
        return s * (1.0 / n) * (2.0 * pi / n);
    };
    if (type == VKRT_SHAPE_SPHERE) {
        for (int i = 0; i < n; ++i) {
            const double theta = pi * (i + 0.5) / n;
            for (int j = 0; j < n; ++j) {
                const double phi = 2.0 * pi * (j + 0.5) / n;
                const glm::dvec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                                   std::sin(theta) * std::sin(phi));
                const glm::dvec3 dTheta(std::cos(theta) * std::cos(phi), -std::sin(theta),
                                        std::cos(theta) * std::sin(phi));
                const glm::dvec3 dPhi(-std::sin(theta) * std::sin(phi), 0.0, std::sin(theta) * std::cos(phi));
                sum += f(linear * p) * element(dTheta, dPhi);
            }
        }
        return sum * (pi / n) * (2.0 * pi / n);
    }
    if (type == VKRT_SHAPE_BOX) {
        for (int axis = 0; axis < 3; ++axis) {
            for (const double side : {-1.0, 1.0}) {
                glm::dvec3 corner(-1.0), a(0.0), b(0.0);
                corner[axis] = side;
                a[(axis + 1) % 3] = 2.0;
                b[(axis + 2) % 3] = 2.0;
                sum += flatFace(corner, a, b);
            }
        }
        return sum;
    }
    if (type == VKRT_SHAPE_CYLINDER) {
        // The side: (sin phi, y, cos phi), dp/dphi = (cos, 0, -sin), dp/dy = (0, 1, 0).
        for (int i = 0; i < n; ++i) {
            const double y = -1.0 + 2.0 * (i + 0.5) / n;
            for (int j = 0; j < n; ++j) {
                const double phi = 2.0 * pi * (j + 0.5) / n;
                const glm::dvec3 p(std::sin(phi), y, std::cos(phi));
                sum += f(linear * p) * element({std::cos(phi), 0, -std::sin(phi)}, {0, 1, 0}) * (2.0 / n) *
                       (2.0 * pi / n);
            }
        }
        return sum + disk(-1.0) + disk(1.0);
    }
    // The cone's side: (w/2 sin phi, 1 - w, w/2 cos phi) for w in [0, 2]; dp/dw = (sin/2, -1, cos/2),
    // dp/dphi = w/2 (cos, 0, -sin).
    for (int i = 0; i < n; ++i) {
        const double w = 2.0 * (i + 0.5) / n;
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * pi * (j + 0.5) / n;
            const glm::dvec3 p(0.5 * w * std::sin(phi), 1.0 - w, 0.5 * w * std::cos(phi));
            sum += f(linear * p) * 0.5 * w *
                   element({0.5 * std::sin(phi), -1.0, 0.5 * std::cos(phi)},
                           {std::cos(phi), 0, -std::sin(phi)}) *
                   (2.0 / n) * (2.0 * pi / n);
        }
    }
    return sum + disk(-1.0);
}

// The ellipsoid's area with Nanson's factor written out: |det M| |M^-T n| over the unit sphere's area
// element.
double ellipsoidAreaByNanson(const glm::dmat3& linear, int n) {
    const glm::dmat3 inverseTranspose = glm::transpose(glm::inverse(linear));
    const double determinant = std::abs(glm::determinant(linear));
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double theta = M_PI * (i + 0.5) / n;
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * M_PI * (j + 0.5) / n;
            const glm::dvec3 normal(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                    std::cos(theta));
            sum += determinant * glm::length(inverseTranspose * normal) * std::sin(theta);
        }
    }
    return sum * (M_PI / n) * (2.0 * M_PI / n);
}

// Where a ray from `origin` along `direction` first meets a shape of `type` placed by `toObject` (its
// inverse), away from the face's rim, a sphere's poles, a side's axis and the seam of u (where differences
// cross to another face or wrap): the hit, and two points 1e-6 away on the same face along two tangent
// directions, with the differences of their texture coordinates from the hit's. False where there is none.
struct FacePatch {
    shading::ShapePoint hit;
    uint32_t face = 0;
    glm::dvec3 p1, p2;
    glm::dvec2 uv, d1, d2;
};

bool facePatch(uint32_t type, const glm::dmat4& toObject, const glm::dvec3& origin,
               const glm::dvec3& direction, FacePatch& patch) {
    const glm::dvec3 o = transformPoint(toObject, origin), d(toObject * glm::dvec4(direction, 0.0));
    double tIn, tOut;
    uint32_t faceOut;
    if (!shading::shapeInterval(type, o, d, tIn, tOut, patch.face, faceOut)) return false;
    const uint32_t face = patch.face;
    patch.hit = shading::shapePoint(type, face, false, shading::affineRows(toObject), origin, direction, tIn);
    const glm::dvec3 p = patch.hit.local;
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    const glm::dvec3 a = glm::abs(p);
    const int axis = static_cast<int>(face / 2u);
    const double rim = type == VKRT_SHAPE_BOX ? std::max(a[(axis + 1) % 3], a[(axis + 2) % 3])
                       : type == VKRT_SHAPE_SPHERE || face == VKRT_FACE_SIDE ? a.y
                                                                             : rho;
    if (rim > 0.999 || (type != VKRT_SHAPE_BOX && face == VKRT_FACE_SIDE && rho < 1e-2)) return false;
    const glm::dvec3 objectNormal = shading::shapeNormal(type, face, p);
    const glm::dvec3 t1 = glm::normalize(glm::cross(objectNormal, glm::dvec3(0.3, 0.5, 0.8)));
    const glm::dvec3 t2 = glm::cross(objectNormal, t1);
    constexpr double kStep = 1e-6;
    patch.p1 = shading::shapeSnap(type, face, p + kStep * t1);
    patch.p2 = shading::shapeSnap(type, face, p + kStep * t2);
    patch.uv = shading::shapeUv(type, face, p);
    patch.d1 = shading::shapeUv(type, face, patch.p1) - patch.uv;
    patch.d2 = shading::shapeUv(type, face, patch.p2) - patch.uv;
    return std::abs(patch.d1.x) <= 0.25 && std::abs(patch.d2.x) <= 0.25;  // not across u's seam
}

TEST(ShapeGeometry, TangentFramesFollowTheTextureCoordinates) {
    // Where a ray meets each face of each shape under an affine map with shear and a mirror, shapeTangent
    // gives the frame a normal texture expects (glTF 2.0, 3.9.3; tangent_frames.cpp for meshes): a unit
    // tangent perpendicular to the normal, along the tangential part of dP/du, and a bitangent w *
    // cross(normal, tangent) on the side of -dP/dv (up the texture), with dP/du and dP/dv found from
    // differences of shapeUv between nearby points of the face; with the normal reversed too (a CSG
    // difference's inner faces). Under a KHR_texture_transform that turns, stretches or mirrors the texture,
    // the frame is that of the transformed coordinates, [dP/du dP/dv] R^-1: the shapes' frames ignored the
    // transform, and a turned normal texture was lit from the side. A VKRT_sphere's frame (sphereTangent) is
    // the sphere shape's under the identity.
    const glm::dmat4 toWorld = shearedMirror();
    const glm::dmat4 toObject = glm::inverse(toWorld);
    const shading::AffineRows toWorldRows = shading::affineRows(toWorld);
    const shading::AffineRows identity = shading::affineRows(glm::dmat4(1.0));
    const glm::dvec3 center(toWorld[3]);
    struct Turn {
        const char* name;
        glm::dvec2 row0, row1;  // (u', v') = (row0 . (u, v), row1 . (u, v))
    };
    const double c = std::cos(0.7), s = std::sin(0.7);
    const Turn turns[] = {{"none", {1.0, 0.0}, {0.0, 1.0}},
                          {"turned and stretched", {1.3 * c, 0.6 * s}, {-1.3 * s, 0.6 * c}},
                          {"mirrored", {-1.0, 0.0}, {0.0, 2.0}},
                          {"turned a quarter", {0.0, 1.0}, {-1.0, 0.0}}};
    for (const uint32_t type : kShapeTypes) {
        SCOPED_TRACE(shapeName(type));
        std::mt19937_64 rng(3000 + type);
        int checked = 0;
        for (int i = 0; i < 1000; ++i) {
            const glm::dvec3 origin = center + 4.0 * randomUnit(rng);
            const glm::dvec3 direction = glm::normalize(center + 0.8 * randomUnit(rng) - origin);
            FacePatch patch;
            if (!facePatch(type, toObject, origin, direction, patch)) continue;
            const shading::ShapePoint& hit = patch.hit;
            const uint32_t face = patch.face;
            const glm::dvec3 p = hit.local, p1 = patch.p1, p2 = patch.p2;
            const glm::dvec2 d1 = patch.d1, d2 = patch.d2;
            const double determinant = d1.x * d2.y - d2.x * d1.y;
            const glm::dvec3 e1 = p1 - p, e2 = p2 - p;
            const glm::dvec3 dpdu(toWorld * glm::dvec4((e1 * d2.y - e2 * d1.y) / determinant, 0.0));
            const glm::dvec3 dpdv(toWorld * glm::dvec4((e2 * d1.x - e1 * d2.x) / determinant, 0.0));
            for (const Turn& turn : turns) {
                SCOPED_TRACE(turn.name);
                // The transformed coordinates' derivatives: columns of R^-1 (glm's matrices are
                // column-major).
                const glm::dmat2 inverse =
                    glm::inverse(glm::dmat2(turn.row0.x, turn.row1.x, turn.row0.y, turn.row1.y));
                const glm::dvec3 dpduTurned = inverse[0][0] * dpdu + inverse[0][1] * dpdv;
                const glm::dvec3 dpdvTurned = inverse[1][0] * dpdu + inverse[1][1] * dpdv;
                for (const bool flip : {false, true}) {
                    const glm::dvec3 normal = flip ? -hit.normal : hit.normal;
                    const glm::dvec4 frame =
                        shading::shapeTangent(type, face, p, toWorldRows, normal, turn.row0, turn.row1);
                    const glm::dvec3 tangent(frame);
                    EXPECT_NEAR(glm::length(tangent), 1.0, 1e-12) << "ray " << i;
                    EXPECT_NEAR(glm::dot(tangent, normal), 0.0, 1e-12) << "ray " << i;
                    EXPECT_GT(
                        glm::dot(tangent, glm::normalize(dpduTurned - normal * glm::dot(normal, dpduTurned))),
                        1.0 - 1e-6)
                        << "ray " << i;
                    EXPECT_TRUE(frame.w == 1.0 || frame.w == -1.0) << "ray " << i;
                    EXPECT_GT(glm::dot(frame.w * glm::cross(normal, tangent), -dpdvTurned), 0.0)
                        << "ray " << i;
                }
                if (type == VKRT_SHAPE_SPHERE) {
                    const glm::dvec4 canonical =
                        shading::shapeTangent(type, face, p, identity, p, turn.row0, turn.row1);
                    EXPECT_LT(glm::length(shading::sphereTangent(p, turn.row0, turn.row1) - canonical), 1e-12)
                        << "ray " << i;
                }
            }
            ++checked;
        }
        EXPECT_GT(checked, 200);
    }
}

// The texture density a shape's mip level comes from (shapeTextureDensity) is, at every point of every face,
// the square root of the ratio of the areas a small patch covers in texture and object space (as on a
// triangle), over the map's scale: shapeUv differenced between nearby points, under a uniform scale of 3. It
// was 0.5 everywhere, right on a box and the flat caps only: a sphere shape read textures 1.15 levels
// blurrier than a VKRT_sphere of its size (a checker of 2-texel squares seen at 1.9 texels a pixel came out
// grey).
TEST(ShapeGeometry, TextureDensityIsTheRatioOfAreasOnEveryFace) {
    const glm::dmat4 toObject = glm::inverse(glm::scale(glm::dmat4(1.0), glm::dvec3(3.0)));
    for (const uint32_t type : kShapeTypes) {
        SCOPED_TRACE(shapeName(type));
        std::mt19937_64 rng(4000 + type);
        int checked = 0;
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 origin = 12.0 * randomUnit(rng);
            const glm::dvec3 direction = glm::normalize(2.4 * randomUnit(rng) - origin);
            FacePatch patch;
            if (!facePatch(type, toObject, origin, direction, patch)) continue;
            const glm::dvec3 p = patch.hit.local, p1 = patch.p1, p2 = patch.p2;
            const glm::dvec2 uv = patch.uv, d1 = patch.d1, d2 = patch.d2;
            const uint32_t face = patch.face;
            const double textureArea = std::abs(d1.x * d2.y - d2.x * d1.y);
            const double objectArea = glm::length(glm::cross(p1 - p, p2 - p));
            const double expected = std::sqrt(textureArea / objectArea) / 3.0;
            EXPECT_NEAR(shading::shapeTextureDensity(type, face, uv, 27.0), expected, 1e-4 * expected)
                << "face " << face << " at " << p.x << " " << p.y << " " << p.z;
            ++checked;
        }
        EXPECT_GT(checked, 400);
    }
}

TEST(ShapeLight, DensitiesIntegrateToTheTrueWorldArea) {
    // Points from sampleShapePoint with density shapePointDensity (per world area): E[1/density] is the
    // surface's world area, and E[f/density] the integral of f over it, for any f. Exact for the box (the
    // density is constant on each face) against the closed form 4 |M a x M b| per face; the ellipsoid, the
    // sheared cylinder and the cone within 5 standard errors (from the samples) of quadrature.
    struct Case {
        const char* name;
        uint32_t type;
        glm::dmat4 toWorld;
    };
    glm::dmat4 shearY(1.0);
    shearY[1][0] = 0.6;   // x += 0.6 y
    shearY[1][2] = -0.3;  // z -= 0.3 y
    glm::dmat4 shearXZ(1.0);
    shearXZ[0][1] = 0.4;   // y += 0.4 x
    shearXZ[2][0] = 0.25;  // x += 0.25 z
    const Case cases[] = {
        {"box", VKRT_SHAPE_BOX, trs({0.3, -0.2, 0.1}, 0.7, {1, 2, 3}, {0.5, 1.2, 0.8}) * shearXZ},
        {"ellipsoid", VKRT_SHAPE_SPHERE, trs({1.0, 0.5, -2.0}, 0.6, {1, 1, 0}, {1.0, 0.5, 2.0})},
        {"sheared cylinder", VKRT_SHAPE_CYLINDER,
         glm::translate(glm::dmat4(1.0), {0.0, 1.0, 0.0}) * shearY *
             glm::scale(glm::dmat4(1.0), {0.7, 1.5, 0.4})},
        {"cone", VKRT_SHAPE_CONE, trs({-0.5, 0.0, 0.7}, 1.1, {0, 1, 1}, {0.8, 1.3, 0.5}) * shearXZ},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const glm::dmat3 linear(c.toWorld);
        const glm::dvec3 translation(c.toWorld[3]);
        const shading::AffineRows toObject = shading::affineRows(glm::inverse(c.toWorld));
        // A smooth weight over the world surface: checks where the points fall, not only how many.
        const glm::dvec3 tilt(0.3, -0.5, 0.8);
        auto weight = [&](glm::dvec3 world) {
            return 1.0 + std::pow(glm::dot(world - translation, tilt) + 0.4, 2.0);
        };

        double trueArea, trueWeighted;
        if (c.type == VKRT_SHAPE_BOX) {
            trueArea = 0.0;
            for (int axis = 0; axis < 3; ++axis) {
                trueArea +=
                    2.0 * 4.0 * glm::length(glm::cross(linear[(axis + 1) % 3], linear[(axis + 2) % 3]));
            }
            EXPECT_NEAR(surfaceIntegral(
                            c.type, linear, [](glm::dvec3) { return 1.0; }, 200),
                        trueArea, 1e-9 * trueArea);
        } else {
            trueArea = surfaceIntegral(c.type, linear, [](glm::dvec3) { return 1.0; });
        }
        if (c.type == VKRT_SHAPE_SPHERE) {
            // The ellipsoid's area from Nanson's factor, written here, over the sphere's own parametrisation
            // (about z), and from the tangents' cross product (about y) agree.
            const double byNanson = ellipsoidAreaByNanson(linear, 1500);
            EXPECT_NEAR(byNanson, trueArea, 1e-5 * trueArea);
            trueArea = byNanson;
        }
        trueWeighted = surfaceIntegral(c.type, linear, [&](glm::dvec3 p) { return weight(p + translation); });

        std::mt19937_64 rng(31 + c.type);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        constexpr int kCount = 400000;
        double sum = 0.0, sum2 = 0.0, weighted = 0.0, weighted2 = 0.0;
        for (int i = 0; i < kCount; ++i) {
            uint32_t face = 0;
            const glm::dvec3 local =
                shading::sampleShapePoint(c.type, toObject, uniform(rng), uniform(rng), face);
            const double density = shading::shapePointDensity(c.type, face, local, toObject);
            ASSERT_GT(density, 0.0);
            // The point is on the face it names.
            ASSERT_LT(glm::length(shading::shapeSnap(c.type, face, local) - local), 1e-12) << "face " << face;
            const double x = 1.0 / density, y = weight(transformPoint(c.toWorld, local)) / density;
            sum += x;
            sum2 += x * x;
            weighted += y;
            weighted2 += y * y;
        }
        const double mean = sum / kCount,
                     error = std::sqrt(std::max(0.0, sum2 / kCount - mean * mean) / kCount);
        const double meanWeighted = weighted / kCount,
                     errorWeighted =
                         std::sqrt(std::max(0.0, weighted2 / kCount - meanWeighted * meanWeighted) / kCount);
        std::printf("%s: area %.6f, estimate %.6f +- %.6f; weighted %.6f, estimate %.6f +- %.6f\n", c.name,
                    trueArea, mean, error, trueWeighted, meanWeighted, errorWeighted);
        EXPECT_NEAR(mean, trueArea, 5.0 * error + 1e-9 * trueArea);
        EXPECT_NEAR(meanWeighted, trueWeighted, 5.0 * errorWeighted + 1e-6 * trueWeighted);
        // The renderer's own estimate of the area (its part weights), exact for boxes, near for the rest.
        const double estimate = shading::shapeArea(c.type, toObject);
        if (c.type == VKRT_SHAPE_BOX) {
            EXPECT_NEAR(estimate, trueArea, 1e-9 * trueArea);
        }
    }
}

// ---------------------------------------------------------------------------------------------------------
// Silhouettes

// `size` x `size` pixels, `spp` samples each, of what the surfaces seen emit (no ambient light, no bounce).
RenderSettings emissionAlone(int size, int spp = 1) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = spp;
    settings.ambient = glm::dvec3(0.0);
    settings.maxDepth = 0;
    return settings;
}

// An orthographic view of half-size `half` looking down -z at the origin from 5 half-sizes away.
Camera alongMinusZ(double half) {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.0, 0.0, 5.0 * half};
    camera.xmag = camera.ymag = half;
    return camera;
}

// An orthographic view of half-size `half` along -x at `centre`, from 3 units away.
Camera alongMinusX(const glm::dvec3& centre, double half) {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = centre + glm::dvec3(3.0, 0.0, 0.0);
    camera.forward = {-1.0, 0.0, 0.0};
    camera.up = {0.0, 1.0, 0.0};
    camera.right = glm::cross(camera.forward, camera.up);
    camera.xmag = camera.ymag = half;
    return camera;
}

Material lampMaterial() {
    Material lamp;
    lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    lamp.emission = glm::vec3(1.0f);
    return lamp;
}

// An emitting solid (radiance 1) against black, seen head-on along -z by an orthographic camera of film
// [-1, 1]^2: the image's mean times the film's area 4 is the solid's projected area, on the GPU and the CPU,
// within 0.2% (as Gpu.SphereSilhouetteMatchesItsAnalyticArea).
struct Silhouette {
    std::string name;
    std::vector<Shape> shapes;
    Table inside;
    double area;
};

void expectSilhouettes(const std::vector<Silhouette>& cases,
                       const std::function<RenderResult(const Scene&, const FlatBvh&, const Camera&,
                                                        const RenderSettings&)>& gpu) {
    const RenderSettings settings = emissionAlone(96, 64);
    const Camera camera = alongMinusZ(1.0);
    for (const Silhouette& c : cases) {
        Scene scene;
        scene.materials.push_back(lampMaterial());
        addSolid(scene, c.shapes, c.inside);
        finalizeScene(scene);
        // A solid of one shape is rendered by a kernel whose loops over a solid's shapes fold away, one of
        // several by a kernel whose loops take that many passes.
        EXPECT_EQ(detectFeatures(scene).csg, c.shapes.size() > 1) << c.name;
        EXPECT_EQ(detectFeatures(scene).solidShapes, c.shapes.size()) << c.name;
        const FlatBvh bvh = bvhFor(scene);
        const Image onGpu = gpu(scene, bvh, camera, settings).image;
        const Image onCpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (const Image* image : {&onGpu, &onCpu}) {
            double sum = 0.0;
            for (const glm::vec3& p : image->pixels) sum += p.x;
            const double area = 4.0 * sum / static_cast<double>(image->pixels.size());
            const char* which = image == &onGpu ? "gpu" : "cpu";
            std::printf("%s (%s): area %.5f, expected %.5f\n", c.name.c_str(), which, area, c.area);
            EXPECT_NEAR(area, c.area, 0.002 * c.area) << c.name << " " << which;
        }
    }
}

Table insideOne() {
    return truthTable(1, [](uint32_t s) { return s == 1u; });
}

TEST_F(ShapeGpu, SilhouettesOfShapesMatchTheirAnalyticAreas) {
    const glm::dvec3 z(0.0, 0.0, 1.0);
    const glm::dmat4 box = glm::scale(glm::dmat4(1.0), {0.5, 0.3, 0.2});
    // A box turned about x and y: its shadow along z is its three visible faces' projections, each 4 |det| of
    // the 2 x 2 projected edge pair.
    const glm::dmat4 tumbled = trs({0.05, -0.1, 0.0}, 0.9, {1.0, 0.7, 0.2}, {0.35, 0.25, 0.3});
    double tumbledArea = 0.0;
    for (int a = 0; a < 3; ++a) {
        const glm::dvec3 u(tumbled[(a + 1) % 3]), v(tumbled[(a + 2) % 3]);
        tumbledArea += 4.0 * std::abs(u.x * v.y - u.y * v.x);
    }
    // An ellipsoid under a rotation off the view axis: its shadow is the ellipse {B u : |u| <= 1} of B, the
    // top two rows of the linear part, of area pi sqrt(det(B B^T)).
    const glm::dmat4 ellipsoid = trs({0.1, 0.05, 0.0}, 0.7, {1.0, -0.4, 0.3}, {0.7, 0.4, 0.5});
    double bbt[2][2] = {{0, 0}, {0, 0}};
    for (int r = 0; r < 2; ++r) {
        for (int s = 0; s < 2; ++s) {
            for (int k = 0; k < 3; ++k) bbt[r][s] += ellipsoid[k][r] * ellipsoid[k][s];
        }
    }
    const double ellipsoidArea = M_PI * std::sqrt(bbt[0][0] * bbt[1][1] - bbt[0][1] * bbt[1][0]);
    const std::vector<Silhouette> cases = {
        {"box face-on", {makeShape(VKRT_SHAPE_BOX, 0, box)}, insideOne(), 1.0 * 0.6},
        {"box turned 30 degrees about the view axis",
         {makeShape(VKRT_SHAPE_BOX, 0, glm::rotate(glm::dmat4(1.0), M_PI / 6.0, z) * box)},
         insideOne(),
         1.0 * 0.6},
        {"box tumbled", {makeShape(VKRT_SHAPE_BOX, 0, tumbled)}, insideOne(), tumbledArea},
        // A sheet 1e-5 thick seen from 5 units: both its faces lie within one CSG tie of the distance (2^-18
        // of it), where a shape's exit once cancelled its own entry and the sheet vanished.
        {"sheet thinner than the tie",
         {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), {0.5, 0.3, 5e-6}))},
         insideOne(),
         1.0 * 0.6},
        // Radius 0.4, height 1.4, axis along y: a 0.8 x 1.4 rectangle.
        {"cylinder from the side",
         {makeShape(VKRT_SHAPE_CYLINDER, 0, glm::scale(glm::dmat4(1.0), {0.4, 0.7, 0.4}))},
         insideOne(),
         0.8 * 1.4},
        // Radius 0.45, axis turned onto the view axis: a disk.
        {"cylinder from above",
         {makeShape(VKRT_SHAPE_CYLINDER, 0, trs({0.0, 0.0, 0.0}, M_PI / 2.0, {1, 0, 0}, {0.45, 0.6, 0.45}))},
         insideOne(),
         M_PI * 0.45 * 0.45},
        // Base radius 0.5, height 1.4: a triangle of base 1 and height 1.4.
        {"cone from the side",
         {makeShape(VKRT_SHAPE_CONE, 0, glm::scale(glm::dmat4(1.0), {0.5, 0.7, 0.5}))},
         insideOne(),
         0.5 * 1.0 * 1.4},
        // Semi-axes 0.7 and 0.4 across the view, turned about it: an ellipse pi a b.
        {"ellipsoid across the view",
         {makeShape(VKRT_SHAPE_SPHERE, 0, trs({0, 0, 0}, 0.4, z, {0.7, 0.4, 0.9}))},
         insideOne(),
         M_PI * 0.7 * 0.4},
        {"ellipsoid tilted off the view axis",
         {makeShape(VKRT_SHAPE_SPHERE, 0, ellipsoid)},
         insideOne(),
         ellipsoidArea},
    };
    expectSilhouettes(cases, [&](const Scene& s, const FlatBvh& b, const Camera& c, const RenderSettings& r) {
        return renderGpu(s, b, c, r);
    });
}

// Shapes 1e-20 across: their bounds, once squared in float, vanished and the shapes with them on both
// devices. The CPU renders them as their analytic areas say; the GPU, whose float tests square the direction
// in the shape's space (1e20 times the world's), refuses them in one line naming --device cpu.
TEST_F(ShapeGpu, ShapesFarSmallerThanFloatsSquaresRenderOnTheCpu) {
    const double size = 1e-20;
    const RenderSettings settings = emissionAlone(32, 4);
    const Camera camera = alongMinusZ(size);
    for (const uint32_t type : {VKRT_SHAPE_SPHERE, VKRT_SHAPE_CONE}) {
        SCOPED_TRACE(shapeName(type));
        Scene scene;
        scene.materials.push_back(lampMaterial());
        // A sphere of radius `size` fills the film's inscribed disk; a cone seen from its side, a triangle of
        // half the film.
        addSolid(scene, {makeShape(type, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(size)))}, insideOne());
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        double sum = 0.0;
        for (const glm::vec3& p : cpu.pixels) sum += p.x;
        EXPECT_NEAR(sum / static_cast<double>(cpu.pixels.size()),
                    type == VKRT_SHAPE_SPHERE ? M_PI / 4.0 : 0.5, 0.03);
        try {
            renderGpu(scene, bvh, camera, settings);
            ADD_FAILURE() << "rendered on the GPU";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("--device cpu"), std::string::npos) << e.what();
        }
    }
    // A shape of 1e-10 in a scene reaching 1e10: rays from as far away square 1e20 in its space.
    Scene wide;
    wide.materials.push_back(lampMaterial());
    addSolid(wide, {makeShape(VKRT_SHAPE_SPHERE, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(1e-10)))},
             insideOne());
    addFlatTriangle(wide, {1e10f, 0.0f, 0.0f}, {1e10f, 1.0f, 0.0f}, {1e10f, 0.0f, 1.0f}, 0);
    finalizeScene(wide);
    try {
        renderGpu(wide, bvhFor(wide), alongMinusZ(1e-10), settings);
        ADD_FAILURE() << "rendered on the GPU";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("seen from up to 5e17 times their size"), std::string::npos)
            << e.what();
    }
}

// A black and white checker of `square`-texel squares, RGBA8.
std::vector<uint32_t> checkerTexels(int width, int height, int square) {
    std::vector<uint32_t> texels;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            texels.push_back(((x / square + y / square) % 2 == 0) ? 0xffffffffu : 0xff000000u);
        }
    }
    return texels;
}

// A scene of one material, white Lambertian (no specular layer: the albedo alone under ambient 1), whose
// albedo is a checker of `square`-texel squares read NEAREST_MIPMAP_NEAREST: every level black and white, its
// mipmaps grey, so a pixel tells which level was read.
Scene checkerScene(int width, int height, int square) {
    Scene scene;
    scene.textures.push_back(test::textureOf(width, height, checkerTexels(width, height, square)));
    scene.textures[0].minNearest = true;
    scene.textures[0].mipmaps = MipmapMode::Nearest;
    Material checker = test::lambertian(1.0f);
    checker.ior = 1.0f;
    checker.baseColorTexture.texture = 0;
    scene.materials = {checker};
    return scene;
}

// An orthographic camera on +z looking at the origin, seeing `halfSize` either side of it.
Camera frontView(double halfSize) {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.0, 0.0, 5.0};
    camera.xmag = camera.ymag = halfSize;
    return camera;
}

// A CSG object's shapes each have their own texture scale: the level of detail on a shape is its own. A box
// of half-size 0.5 seen face-on by n = 16 pixels across its face reads a 64-texel checker of 4-texel squares
// at level log2(64 / 16) = 2, one texel a pixel (NEAREST_MIPMAP_NEAREST): every pixel black or white, as the
// box alone. With a tiny sphere as the union's first operand, whose scale once set the object's level, the
// box came out the mip chain's grey.
TEST_F(ShapeGpu, EachShapeOfACsgObjectReadsTexturesAtItsOwnScale) {
    const Camera camera = frontView(0.5);
    RenderSettings settings = test::ambientOnly(16);
    settings.maxDepth = 0;
    const glm::dmat4 box = glm::scale(glm::dmat4(1.0), glm::dvec3(0.5));
    const glm::dmat4 speck =
        glm::translate(glm::dmat4(1.0), {0.0, 0.0, -1.0}) * glm::scale(glm::dmat4(1.0), glm::dvec3(0.01));
    for (const bool withSpeck : {false, true}) {
        Scene scene = checkerScene(64, 64, 4);
        if (withSpeck) {
            addSolid(scene, {makeShape(VKRT_SHAPE_SPHERE, 0, speck), makeShape(VKRT_SHAPE_BOX, 0, box)},
                     truthTable(2, [](uint32_t s) { return s != 0u; }));
        } else {
            addSolid(scene, {makeShape(VKRT_SHAPE_BOX, 0, box)}, insideOne());
        }
        finalizeScene(scene);
        const test::RenderPair pair =
            test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
        const Image &gpu = pair.gpu.image, &cpu = pair.cpu.image;
        for (const Image* image : {&gpu, &cpu}) {
            int checkerPixels = 0;
            for (const glm::vec3& pixel : image->pixels)
                checkerPixels += pixel.x < 1e-5f || pixel.x > 1.0f - 1e-5f;
            EXPECT_EQ(checkerPixels, 256)
                << (withSpeck ? "with a speck first" : "alone") << ", " << (image == &gpu ? "gpu" : "cpu");
        }
    }
}

// A sphere shape reads a mipmapped texture at a VKRT_sphere's level: a checker of 2-texel squares (256 x
// 128), seen orthographically at 1.9 texels a pixel across the equator, is read at level 1
// (NEAREST_MIPMAP_NEAREST), still black and white. The shape read level 2, every pixel of the equator's row
// grey.
TEST_F(ShapeGpu, SphereShapeReadsTexturesAtTheSpheresLevel) {
    const Camera camera = frontView(1.1);
    RenderSettings settings = test::ambientOnly(48);
    settings.samplesPerPixel = 1;  // each pixel one texel of the level read
    settings.maxDepth = 0;
    std::array<test::RenderPair, 2> pairs;
    for (const bool shape : {false, true}) {
        Scene scene = checkerScene(256, 128, 2);
        if (shape) {
            addSolid(scene, {makeShape(VKRT_SHAPE_SPHERE, 0, glm::dmat4(1.0))}, insideOne());
        } else {
            scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        }
        finalizeScene(scene);
        pairs[shape] =
            test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
    }
    for (const bool gpu : {false, true}) {
        SCOPED_TRACE(gpu ? "gpu" : "cpu");
        const Image& sphere = gpu ? pairs[0].gpu.image : pairs[0].cpu.image;
        const Image& shape = gpu ? pairs[1].gpu.image : pairs[1].cpu.image;
        // The rows about the equator, inside the disk.
        int blackOrWhite = 0, same = 0, pixels = 0;
        for (int y = 22; y < 26; ++y) {
            for (int x = 12; x < 36; ++x) {
                const float value = shape.pixels[y * 48 + x].x;
                blackOrWhite += value < 0.02f || value > 0.98f;
                same += std::abs(value - sphere.pixels[y * 48 + x].x) < 0.02f;
                ++pixels;
            }
        }
        EXPECT_GT(blackOrWhite, pixels * 9 / 10);
        EXPECT_GT(same, pixels * 9 / 10);
    }
}

// A normal texture turns the normals of a VKRT_sphere and of a sphere shape (plain, turned about +y,
// mirrored) as it turns those of a finely tessellated sphere whose tangents point east, the way u grows, with
// the bitangent north, up the texture: tilted towards the bitangent (north) and towards the tangent (east)
// under a sun from the upper right, each image is the mesh's within 1% of the brightest inside the disk (away
// from the silhouette, where the facets cover pixels differently); the mirrored shape's tangent points west,
// so only the northward tilt is the same there. Both devices, and each a clear change from the sphere without
// a map.
TEST_F(ShapeGpu, NormalTexturesTurnSpheresAndShapesAsMeshes) {
    RenderSettings settings;
    settings.integrator = Integrator::Whitted;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 4;
    settings.ambient = glm::dvec3(0.0);
    PunctualLight sun;
    sun.type = LightType::Directional;
    sun.direction = -glm::normalize(glm::vec3(0.3f, 0.4f, 1.0f));
    sun.intensity = 2.0f;
    Material white = test::lambertian(1.0f);
    // The maps' one texel in tangent space: none, towards the bitangent, towards the tangent.
    const uint32_t flat = 0xffff8080u, north = 0xffe0cc80u, east = 0xffe080ccu;
    enum class Surface { Mesh, Sphere, Shape, TurnedShape, MirroredShape };
    auto render = [&](Surface surface, uint32_t texel) {
        Scene scene;
        scene.lights.push_back(sun);
        scene.textures.push_back(test::textureOf(1, 1, {texel}));
        Material material = white;
        material.normalTexture.texture = 0;
        scene.materials.push_back(material);
        if (surface == Surface::Mesh) {
            test::addUvSphereMesh(scene, 64, 128, 0, true);
        } else if (surface == Surface::Sphere) {
            scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        } else {
            const glm::dmat4 pose = surface == Surface::TurnedShape
                                        ? trs({}, 0.7, {0.0, 1.0, 0.0}, glm::dvec3(1.0))
                                    : surface == Surface::MirroredShape ? trs({}, 0.0, {}, {-1.0, 1.0, 1.0})
                                                                        : glm::dmat4(1.0);
            addSolid(scene, {makeShape(VKRT_SHAPE_SPHERE, 0, pose)}, insideOne());
        }
        finalizeScene(scene);
        return test::renderGpuAndCpu(context(), scene, bvhFor(scene), test::sphereCamera(), settings,
                                     test::shaderCacheDir());
    };
    // The largest difference of two images inside the disk, and the brightest pixel there of the first.
    auto differenceInDisk = [&](const Image& a, const Image& b, double& brightest) {
        double worst = 0.0;
        brightest = 0.0;
        for (int y = 0; y < settings.height; ++y) {
            for (int x = 0; x < settings.width; ++x) {
                const double u = 2.0 * (x + 0.5) / settings.width - 1.0,
                             v = 2.0 * (y + 0.5) / settings.height - 1.0;
                if (u * u + v * v > 0.8 * 0.8) continue;
                worst = std::max(worst, static_cast<double>(std::abs(a.at(x, y).x - b.at(x, y).x)));
                brightest = std::max(brightest, static_cast<double>(a.at(x, y).x));
            }
        }
        return worst;
    };
    const test::RenderPair plain = render(Surface::Sphere, flat);
    for (const uint32_t texel : {north, east}) {
        const test::RenderPair mesh = render(Surface::Mesh, texel);
        double brightest = 0.0;
        EXPECT_GT(differenceInDisk(mesh.cpu.image, plain.cpu.image, brightest), 0.1 * brightest);
        std::vector<Surface> surfaces = {Surface::Sphere, Surface::Shape, Surface::TurnedShape};
        if (texel == north) surfaces.push_back(Surface::MirroredShape);
        for (const Surface surface : surfaces) {
            SCOPED_TRACE(testing::Message()
                         << (texel == north ? "north" : "east") << ", surface " << static_cast<int>(surface));
            const test::RenderPair pair = render(surface, texel);
            EXPECT_LT(differenceInDisk(mesh.gpu.image, pair.gpu.image, brightest), 0.01 * brightest);
            EXPECT_GT(brightest, 0.2);
            EXPECT_LT(differenceInDisk(mesh.cpu.image, pair.cpu.image, brightest), 0.01 * brightest);
            test::expectMatchesReference(pair.gpu.image, pair.cpu.image, "normal-textured-sphere");
        }
    }
}

TEST_F(ShapeGpu, SilhouettesOfCsgObjectsMatchTheirAnalyticAreas) {
    // A box [-1, 1]^3 scaled by a = 0.5 minus a sphere of radius R = 1.3 a at its centre. Along z, the line
    // at (x, y) inside the square stays inside the sphere over the box's whole depth |z| <= a exactly when
    // x^2 + y^2 + a^2 <= R^2: those lines see nothing. The others meet the box's front face at a point
    // outside the sphere (x^2 + y^2 + a^2 > R^2 there). The silhouette is the square minus the disk of
    // radius sqrt(R^2 - a^2) = 0.415 < a: area 4 a^2 - pi (R^2 - a^2) = 1 - pi 0.69 / 4.
    const double a = 0.5, radius = 1.3 * a;
    const double carvedArea = 4.0 * a * a - M_PI * (radius * radius - a * a);
    // A sphere of radius R = 0.6 intersected with a box of half-side b = 0.5 (its corners, at b sqrt 3 =
    // 0.87, poke out of the sphere): along z the line at (x, y) meets the solid when |x|, |y| <= b and
    // x^2 + y^2 <= R^2 (at z = 0): the square cut by the disk. Its area by quadrature of the columns'
    // lengths, 2 min(b, sqrt(R^2 - x^2)), over x in [-b, b].
    const double b = 0.5, sphereRadius = 0.6;
    double cutArea = 0.0;
    constexpr int kColumns = 1000000;
    for (int i = 0; i < kColumns; ++i) {
        const double x = -b + (i + 0.5) * (2.0 * b / kColumns);
        cutArea += 2.0 * std::min(b, std::sqrt(std::max(0.0, sphereRadius * sphereRadius - x * x))) *
                   (2.0 * b / kColumns);
    }
    ASSERT_LT(cutArea, 4.0 * b * b - 0.01);  // the disk does cut the corners
    const Table difference = truthTable(2, [](uint32_t s) { return bit(s, 0) && !bit(s, 1); });
    const Table intersection = truthTable(2, [](uint32_t s) { return bit(s, 0) && bit(s, 1); });
    const Table unionTable = truthTable(2, [](uint32_t s) { return bit(s, 0) || bit(s, 1); });
    const std::vector<Silhouette> cases = {
        {"box minus a larger sphere",
         {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(a))),
          makeShape(VKRT_SHAPE_SPHERE, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(radius)))},
         difference,
         carvedArea},
        {"sphere intersected with a smaller box",
         {makeShape(VKRT_SHAPE_SPHERE, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(sphereRadius))),
          makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(b)))},
         intersection,
         cutArea},
        // The same box with a sphere of radius 0.3 bitten out of its front face (centred on it): the bowl's
        // faces (the sphere's, reversed) face the camera and emit, so the silhouette is the whole square.
        {"box with a bowl bitten out of its front face",
         {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(a))),
          makeShape(VKRT_SHAPE_SPHERE, 0, trs({0.0, 0.0, a}, 0.0, {0, 0, 1}, glm::dvec3(0.3)))},
         difference,
         4.0 * a * a},
        // Drilled along the view axis by a cylinder of radius 0.2 longer than the box: a square with a hole.
        {"box drilled along the view axis",
         {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(a))),
          makeShape(VKRT_SHAPE_CYLINDER, 0, trs({0.1, -0.05, 0.0}, M_PI / 2.0, {1, 0, 0}, {0.2, 0.8, 0.2}))},
         difference,
         4.0 * a * a - M_PI * 0.2 * 0.2},
        {"two disjoint boxes",
         {makeShape(VKRT_SHAPE_BOX, 0, trs({-0.5, 0.0, 0.0}, 0.0, {0, 0, 1}, {0.3, 0.4, 0.2})),
          makeShape(VKRT_SHAPE_BOX, 0, trs({0.5, 0.0, 0.3}, 0.0, {0, 0, 1}, {0.2, 0.5, 0.1}))},
         unionTable,
         0.6 * 0.8 + 0.4 * 1.0},
    };
    expectSilhouettes(cases, [&](const Scene& s, const FlatBvh& bvh, const Camera& c,
                                 const RenderSettings& r) { return renderGpu(s, bvh, c, r); });
}

// ---------------------------------------------------------------------------------------------------------
// A CSG lamp

TEST_F(ShapeGpu, ACutFlushWithAFaceFarFromTheMiddleStaysOpen) {
    // A box minus a slot cut flush into its +x face (the slot's +x face on the box's), seen along -x into the
    // slot, D units from the scene's middle. The faces meant to coincide are placed apart by the rounding of
    // their float maps, about ulp(D) / 2, and a tie relative to the distance alone (3 units here) sealed the
    // slot with a sliver of the box's face at some D from 300 on, on both devices. Each shape glows in its
    // own colour: the slot's floor is the slot's (green), a seal the box's (red).
    Material red = lampMaterial(), green = lampMaterial();
    red.emission = glm::vec3(1.0f, 0.0f, 0.0f);
    green.emission = glm::vec3(0.0f, 1.0f, 0.0f);
    const RenderSettings settings = emissionAlone(8);
    for (const double distance : {0.0, 97.3, 300.0, 311.7, 1234.5, 3000.0, 9876.5}) {
        SCOPED_TRACE(testing::Message() << "D = " << distance);
        const glm::dvec3 centre(distance, 0.37 * distance, -0.21 * distance);
        Scene scene;
        scene.materials = {red, green};
        const double depth = 0.4;  // the slot's, from the box's face at x = 0.7 inwards
        addSolid(scene,
                 {makeShape(VKRT_SHAPE_BOX, 0, trs(centre, 0.0, {0, 0, 1}, {0.7, 0.9, 0.8})),
                  makeShape(VKRT_SHAPE_BOX, 1,
                            trs(centre + glm::dvec3(0.7 - 0.5 * depth, 0.0, 0.0), 0.0, {0, 0, 1},
                                {0.5 * depth, 0.3, 0.3}))},
                 truthTable(2, [](uint32_t s) { return bit(s, 0) && !bit(s, 1); }));
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        const Camera camera = alongMinusX(centre, 0.25);  // inside the slot's opening of half-size 0.3
        const Image gpu = renderGpu(scene, bvh, camera, settings).image;
        const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (const Image* image : {&gpu, &cpu}) {
            int sealed = 0;
            for (const glm::vec3& p : image->pixels) sealed += !(p.y > 0.99f && p.x < 0.01f);
            EXPECT_EQ(sealed, 0) << (image == &gpu ? "gpu" : "cpu");
        }
    }
}

TEST_F(ShapeGpu, RaysThroughHolesCrossCoincidentFacesOnce) {
    // The intersection of a box of half-size 1 and a wider one whose top face is meant to coincide with it (z
    // from -0.4 to 1, placed by a translation and a scale that round differently), black and of alpha 0.5
    // (BLEND), against a background of 1, seen from an oblique direction: each ray crosses the solid's
    // surface twice, and passes each crossing with probability 0.5, so the image converges to 0.25. A ray
    // that passed a hole searched on from its own shape's face, met the other shape's face just beyond it as
    // a crossing of its own, and passed the top twice: 0.2375 on average.
    Material black = test::lambertian(0.0f);
    black.baseColor.a = 0.5f;
    black.alphaMode = AlphaMode::Blend;
    Scene scene;
    scene.materials.push_back(black);
    addSolid(
        scene,
        {makeShape(VKRT_SHAPE_BOX, 0, trs({0.0, 0.0, 0.0}, 0.0, {0, 0, 1}, {1.0, 1.0, 1.0})),
         makeShape(VKRT_SHAPE_BOX, 0, trs({0.0, 0.0, 0.30000000000000004}, 0.0, {0, 0, 1}, {1.5, 1.5, 0.7}))},
        truthTable(2, [](uint32_t s) { return bit(s, 0) && bit(s, 1); }));
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera = lookAtCamera({1.4, -0.4, 4.8}, glm::dvec3(0.0), Camera{}.yfov);
    camera.projection = Projection::Orthographic;
    camera.xmag = camera.ymag = 0.5;  // every ray enters through the top
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        SCOPED_TRACE(integrator == Integrator::Path ? "paths" : "Whitted");
        RenderSettings settings = emissionAlone(32, 64);
        settings.background = glm::dvec3(1.0);
        settings.integrator = integrator;
        const Image gpu = renderGpu(scene, bvh, camera, settings).image;
        const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (const Image* image : {&gpu, &cpu}) {
            double sum = 0.0;
            for (const glm::vec3& p : image->pixels) sum += p.x;
            EXPECT_NEAR(sum / static_cast<double>(image->pixels.size()), 0.25, 0.002)
                << (image == &gpu ? "gpu" : "cpu");
        }
    }
}

TEST_F(ShapeGpu, ThinWallsFarFromTheMiddleStayWhole) {
    // A hollow box (half-size 0.5 minus 0.45: walls 0.05 thick) seen along -x from 3 units away, 1e5 from
    // the scene's middle: every pixel sees its front wall. A tie of 2^-18 of the coordinates' magnitude (0.38
    // there) took the walls' two faces as one and the box vanished, on both devices.
    const RenderSettings settings = emissionAlone(8);
    for (const double distance : {0.0, 1e5}) {
        SCOPED_TRACE(testing::Message() << "D = " << distance);
        const glm::dvec3 centre(distance, 0.0, 0.0);
        Scene scene;
        scene.materials.push_back(lampMaterial());
        addSolid(scene,
                 {makeShape(VKRT_SHAPE_BOX, 0, trs(centre, 0.0, {0, 0, 1}, glm::dvec3(0.5))),
                  makeShape(VKRT_SHAPE_BOX, 0, trs(centre, 0.0, {0, 0, 1}, glm::dvec3(0.45)))},
                 truthTable(2, [](uint32_t s) { return bit(s, 0) && !bit(s, 1); }));
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        const Camera camera = alongMinusX(centre, 0.4);
        const Image gpu = renderGpu(scene, bvh, camera, settings).image;
        const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (const Image* image : {&gpu, &cpu}) {
            int missed = 0;
            for (const glm::vec3& p : image->pixels) missed += !(p.x > 0.99f);
            EXPECT_EQ(missed, 0) << (image == &gpu ? "gpu" : "cpu");
        }
    }
}

TEST_F(ShapeGpu, CsgLampLightsAFloorAsItsSolidAngleSays) {
    // An emitting CSG object (radiance 1, centred 1.2 above the floor) over a Lambertian floor of albedo 1
    // (no specular layer). The floor's radiance at a point is its irradiance over pi: the cosine-weighted
    // fraction of the hemisphere that sees the lamp, counted here by tracing 10^6 stratified
    // cosine-distributed rays against the scene with the CPU's closestHit. The path integrator (one bounce:
    // light samples of the lamp's shapes, kept only where they lie on the solid's surface, and floor rays
    // that find it, weighed by multiple importance) must give that radiance on the GPU and the CPU, within 5
    // standard errors of the image's mean. Lamps: a box of half-side 0.5 minus a sphere of radius 0.65; and
    // solids whose operands' faces coincide, where light samples asked each shape at the point itself: a
    // union of two identical boxes (which gave a thirtieth of the light), an L of two overlapping boxes with
    // flush faces (two thirds) and two crossed boxes intersected into one (twice the light); and (A and B)
    // or C, three bottoms in one plane, where only C glows: light samples once put the shared bottom's light
    // on A (the choice of a ray leaving the solid), while rays that arrive from below, as the floor's do,
    // cross it on C. Only hits on the lamp's material count.
    const glm::dvec3 center(0.0, 0.0, 1.2);
    const auto box = [&](glm::dvec3 offset, glm::dvec3 half, uint32_t material = 0) {
        return makeShape(VKRT_SHAPE_BOX, material, trs(center + offset, 0.0, {0, 0, 1}, half));
    };
    const Table unionOfTwo = truthTable(2, [](uint32_t s) { return bit(s, 0) || bit(s, 1); });
    struct Lamp {
        const char* name;
        std::vector<Shape> shapes;
        Table inside;
    };
    const std::vector<Lamp> lamps = {
        {"box minus sphere",
         {box({}, glm::dvec3(0.5)),
          makeShape(VKRT_SHAPE_SPHERE, 0, trs(center, 0.0, {0, 0, 1}, glm::dvec3(0.65)))},
         truthTable(2, [](uint32_t s) { return bit(s, 0) && !bit(s, 1); })},
        {"two identical boxes united", {box({}, glm::dvec3(0.5)), box({}, glm::dvec3(0.5))}, unionOfTwo},
        {"an L of two overlapping flush boxes",
         {box({-0.25, 0.0, 0.0}, {0.25, 0.5, 0.5}), box({0.15, -0.25, 0.0}, {0.35, 0.25, 0.5})},
         unionOfTwo},
        {"two crossed boxes intersected",
         {box({}, {0.5, 1.0, 0.5}), box({}, {1.0, 0.5, 0.5})},
         truthTable(2, [](uint32_t s) { return bit(s, 0) && bit(s, 1); })},
        {"a glowing box united with two dark ones intersected, bottoms flush",
         {box({-0.4, 0.0, 0.0}, glm::dvec3(0.5), 1), box({-0.2, 0.3, 0.0}, glm::dvec3(0.5), 1),
          box({}, glm::dvec3(0.5))},
         truthTable(3, [](uint32_t s) { return (bit(s, 0) && bit(s, 1)) || bit(s, 2); })},
    };
    for (const Lamp& lamp : lamps) {
        SCOPED_TRACE(lamp.name);
        Scene scene;
        scene.materials.push_back(lampMaterial());
        Material floor;
        floor.baseColor = glm::vec4(1.0f);
        floor.metallic = 0.0f;  // glTF's default is 1
        floor.specularFactor = 0.0f;
        scene.materials.push_back(floor);
        addSolid(scene, lamp.shapes, lamp.inside);
        addFlatQuad(scene, {-3.0f, -3.0f, 0.0f}, {3.0f, -3.0f, 0.0f}, {3.0f, 3.0f, 0.0f}, {-3.0f, 3.0f, 0.0f},
                    1);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);

        // The lamp's cosine-weighted share of the hemisphere above the point.
        const glm::dvec3 point(0.3, 0.1, 0.0);
        constexpr int kStrata = 1000;
        int64_t seen = 0;
        for (int i = 0; i < kStrata; ++i) {
            for (int j = 0; j < kStrata; ++j) {
                const double u = (i + 0.5) / kStrata, phi = 2.0 * M_PI * (j + 0.5) / kStrata,
                             r = std::sqrt(u);
                const glm::dvec3 direction(r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0 - u));
                SurfaceHit hit;
                if (closestHitBeyond(scene, bvh, {point, direction}, 1e-6, 1e30, kNoPrimitive, hit) &&
                    scene.isSolid(hit.primitive) && scene.shapes[static_cast<size_t>(hit.u)].material == 0) {
                    ++seen;
                }
            }
        }
        const double expected = static_cast<double>(seen) / (double(kStrata) * kStrata);
        ASSERT_GT(expected, 0.05);
        ASSERT_LT(expected, 0.5);

        // A small orthographic view of the floor around the point, from above and aside (clear of the lamp).
        Camera camera;
        camera.projection = Projection::Orthographic;
        const glm::dvec3 back = glm::normalize(glm::dvec3(1.0, 0.2, 0.6));
        camera.position = point + 3.0 * back;
        camera.forward = -back;
        camera.up = glm::normalize(glm::dvec3(0, 0, 1) - back.z * back);
        camera.right = glm::cross(camera.forward, camera.up);
        camera.xmag = camera.ymag = 0.01;
        RenderSettings settings;
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 1024;
        settings.integrator = Integrator::Path;
        settings.maxDepth = 1;
        settings.ambient = glm::dvec3(0.0);
        for (const bool mis : {true, false}) {
            settings.multipleImportanceSampling = mis;
            const Image gpu = renderGpu(scene, bvh, camera, settings).image;
            const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
            for (const Image* image : {&gpu, &cpu}) {
                double sum = 0.0, sum2 = 0.0;
                for (const glm::vec3& p : image->pixels) {
                    sum += p.x;
                    sum2 += double(p.x) * p.x;
                }
                const double n = static_cast<double>(image->pixels.size()), mean = sum / n;
                const double error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
                const std::string which =
                    std::string(image == &gpu ? "gpu" : "cpu") + (mis ? "" : ", light samples alone");
                std::printf("%s, %s: floor radiance %.5f +- %.5f, the lamp's cosine-weighted share %.5f\n",
                            lamp.name, which.c_str(), mean, error, expected);
                EXPECT_NEAR(mean, expected, 5.0 * error + 1e-3 * expected) << which;
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------------------
// A CSG lens

// A biconvex lens: the intersection of two spheres of radius R whose centres lie `separation` apart on its
// local z axis, thickness d = 2 R - separation; light travels along local -z. The front surface (z = d/2)
// belongs to the sphere centred at -separation/2, the back (z = -d/2) to the one at +separation/2. As in
// scenes/csg.gltf, and placed in the world by `place`, a rotation and a translation.
struct Lens {
    double radius = 1.5;
    double separation = 2.5;
    double index = 1.5;
    glm::dmat4 place = trs({0.3, 0.83, -1.5}, 0.5, {1.0, 1.0, 0.0}, glm::dvec3(1.0));
    glm::dvec3 toWorld(glm::dvec3 local) const { return transformPoint(place, local); }
    glm::dvec3 toWorldDirection(glm::dvec3 local) const { return glm::dvec3(place * glm::dvec4(local, 0.0)); }
    double thickness() const { return 2.0 * radius - separation; }
    // The thick-lens back focal distance: R1 = R > 0, R2 = -R < 0 (centre of curvature behind the surface).
    double backFocalDistance() const {
        const double n = index, d = thickness(), r1 = radius, r2 = -radius;
        const double power = (n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2));
        const double f = 1.0 / power;
        return f * (1.0 - (n - 1.0) * d / (n * r1));
    }
    Scene scene() const {
        Scene s;
        s.materials.push_back(Material{});
        const std::vector<Shape> shapes = {
            makeShape(VKRT_SHAPE_SPHERE, 0,
                      place * trs({0.0, 0.0, -0.5 * separation}, 0.0, {0, 0, 1}, glm::dvec3(radius))),
            makeShape(VKRT_SHAPE_SPHERE, 0,
                      place * trs({0.0, 0.0, 0.5 * separation}, 0.0, {0, 0, 1}, glm::dvec3(radius)))};
        addSolid(s, shapes, truthTable(2, [](uint32_t st) { return st == 3u; }));
        finalizeScene(s);
        return s;
    }
};

struct LensRay {
    glm::dvec3 origin;
    glm::dvec3 direction;
};

// Where a traced ray met the lens: the point, and the solid's outward normal there from shapePoint with the
// shape and face decoded from the hit (u: the scene's shape; v: face * 2 + flip).
struct LensHit {
    bool found = false;
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};
};

LensHit lensHitAt(const Scene& scene, const LensRay& ray, double t, double u, double v) {
    LensHit hit;
    hit.found = true;
    const uint32_t shape = static_cast<uint32_t>(std::lround(u)),
                   code = static_cast<uint32_t>(std::lround(v));
    EXPECT_LT(shape, scene.shapes.size());
    const Shape& s = scene.shapes[std::min<size_t>(shape, scene.shapes.size() - 1)];
    const shading::ShapePoint p = shading::shapePoint(
        s.type, code / 2, (code & 1u) != 0u, shading::affineRows(s.toObject), ray.origin, ray.direction, t);
    hit.point = ray.origin + t * ray.direction;
    hit.normal = p.normal;
    return hit;
}

using LensTracer = std::function<std::vector<LensHit>(const std::vector<LensRay>&, double tMin)>;

struct Focus {
    double paraxial;    // the back focal distance fitted as height -> 0
    double aberration;  // the fit's h^2 coefficient
    double spread;      // the largest difference between rays of one height
};

// Parallel rays along the axis at heights up to 0.05 R, three azimuths each, traced in the world, refracted
// (Snell, by refractThrough) where they enter and leave; each exiting ray crosses the axis at some distance
// beyond the back vertex. The paraxial back focal distance is the fit a + b h^2 of those distances, at h = 0.
Focus measureFocus(const Lens& lens, const Scene& scene, const LensTracer& trace, double tMin) {
    std::vector<LensRay> rays;
    std::vector<double> heights;
    for (int k = 1; k <= 8; ++k) {
        const double h = 0.05 * lens.radius * k / 8.0;
        for (const double azimuth : {0.0, 2.1, 4.2}) {
            rays.push_back({lens.toWorld({h * std::cos(azimuth), h * std::sin(azimuth), 2.0}),
                            lens.toWorldDirection({0.0, 0.0, -1.0})});
            heights.push_back(h);
        }
    }
    for (int crossing = 0; crossing < 2; ++crossing) {
        const std::vector<LensHit> hits = trace(rays, tMin);
        for (size_t i = 0; i < rays.size(); ++i) {
            if (!hits[i].found) {
                ADD_FAILURE() << "ray " << i << " missed the lens at crossing " << crossing;
                return {};
            }
            glm::dvec3 normal = hits[i].normal;
            const glm::dvec3 toViewer = -rays[i].direction;
            const bool entering = glm::dot(toViewer, normal) > 0.0;
            EXPECT_EQ(entering, crossing == 0) << "ray " << i;
            // The surface: the front sphere's at z = d/2 entering, the back one's at -d/2 leaving, on the
            // sphere of radius R about the centre behind it.
            const glm::dvec3 centre = lens.toWorld({0.0, 0.0, (entering ? -0.5 : 0.5) * lens.separation});
            EXPECT_NEAR(glm::distance(hits[i].point, centre), lens.radius, 1e-5) << "ray " << i;
            EXPECT_NEAR(glm::dot(normal, glm::normalize(hits[i].point - centre)), 1.0, 1e-5) << "ray " << i;
            double eta = lens.index;
            if (!entering) {
                normal = -normal;
                eta = 1.0 / lens.index;
            }
            glm::dvec3 refracted;
            EXPECT_TRUE(shading::refractThrough(toViewer, normal, eta, refracted)) << "ray " << i;
            rays[i] = {hits[i].point, glm::normalize(refracted)};
        }
    }
    // Nothing more along the exiting rays.
    for (const LensHit& hit : trace(rays, tMin)) EXPECT_FALSE(hit.found);
    // Where each crosses the axis (nearest approach to it; the rays are meridional). The axis runs through
    // the spheres' centres as the scene stores them (in float: `place` rounded moves it by ~1e-7, which the
    // rays' small angles to the axis would magnify a hundredfold along it).
    const glm::dvec3 front(scene.shapes[0].toWorld[3]), back(scene.shapes[1].toWorld[3]);
    const glm::dvec3 middle = 0.5 * (front + back), along = glm::normalize(front - back);  // the light's way
    std::vector<double> distance(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        const glm::dvec3 offset = rays[i].origin - middle, direction = rays[i].direction;
        const glm::dvec3 offsetAcross = offset - glm::dot(offset, along) * along,
                         directionAcross = direction - glm::dot(direction, along) * along;
        const double t =
            -glm::dot(offsetAcross, directionAcross) / glm::dot(directionAcross, directionAcross);
        EXPECT_GT(t, 0.0) << "ray " << i << " diverges";
        distance[i] = glm::dot(offset + t * direction, along) - 0.5 * lens.thickness();
    }
    // Least squares of distance = a + b h^2.
    double s0 = 0, s1 = 0, s2 = 0, y0 = 0, y1 = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const double x = heights[i] * heights[i];
        s0 += 1;
        s1 += x;
        s2 += x * x;
        y0 += distance[i];
        y1 += x * distance[i];
    }
    Focus focus;
    focus.aberration = (s0 * y1 - s1 * y0) / (s0 * s2 - s1 * s1);
    focus.paraxial = (y0 - focus.aberration * s1) / s0;
    focus.spread = 0.0;
    for (size_t i = 0; i < rays.size(); i += 3) {
        for (size_t j = i + 1; j < i + 3; ++j)
            focus.spread = std::max(focus.spread, std::abs(distance[j] - distance[i]));
    }
    return focus;
}

TEST(ShapeLens, CsgLensFocusesWhereTheThickLensFormulaSaysOnTheCpu) {
    const Lens lens;
    const Scene scene = lens.scene();
    const FlatBvh bvh = bvhFor(scene);
    const LensTracer cpu = [&](const std::vector<LensRay>& rays, double tMin) {
        std::vector<LensHit> hits(rays.size());
        for (size_t i = 0; i < rays.size(); ++i) {
            SurfaceHit hit;
            if (closestHitBeyond(scene, bvh, {rays[i].origin, rays[i].direction}, tMin, 1e30, kNoPrimitive,
                                 hit)) {
                EXPECT_TRUE(scene.isSolid(hit.primitive));
                hits[i] = lensHitAt(scene, rays[i], hit.t, hit.u, hit.v);
            }
        }
        return hits;
    };
    const Focus focus = measureFocus(lens, scene, cpu, 1e-9);
    const double expected = lens.backFocalDistance();
    std::printf("cpu: back focal distance %.9f (aberration %.4f h^2, spread %.2e), thick-lens formula %.9f\n",
                focus.paraxial, focus.aberration, focus.spread, expected);
    EXPECT_NEAR(focus.paraxial, expected, 1e-4 * expected);
    EXPECT_LT(focus.aberration, 0.0);  // marginal rays focus nearer (spherical aberration)
    // The lens is round, to the float rounding of its spheres' stored maps (relative 6e-8: their normals tilt
    // by as much, which moves a focus along the axis by ~f^2 / h times it, up to 1e-5 at the smallest
    // height).
    EXPECT_LT(focus.spread, 5e-5);
}

TEST_F(ShapeGpu, CsgLensFocusesWhereTheThickLensFormulaSaysOnTheGpu) {
    const Lens lens;
    const Scene scene = lens.scene();
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
    const LensTracer gpu = [&](const std::vector<LensRay>& rays, double tMin) {
        std::vector<gpu::GpuRay> batch;
        std::vector<LensRay> rounded;
        for (const LensRay& r : rays) {
            batch.push_back({glm::vec3(r.origin), static_cast<float>(tMin), glm::vec3(r.direction), 1e30f});
            rounded.push_back({glm::dvec3(glm::vec3(r.origin)), glm::dvec3(glm::vec3(r.direction))});
        }
        const std::vector<gpu::GpuHit> found = raycaster.trace(batch, RaycastMode::Closest);
        std::vector<LensHit> hits(rays.size());
        for (size_t i = 0; i < rays.size(); ++i) {
            if (found[i].primitive == VKRT_NO_HIT) continue;
            EXPECT_TRUE(scene.isSolid(found[i].primitive));
            hits[i] = lensHitAt(scene, rounded[i], found[i].t, found[i].u, found[i].v);
        }
        return hits;
    };
    const Focus focus = measureFocus(lens, scene, gpu, 1e-4);
    const double expected = lens.backFocalDistance();
    std::printf("gpu: back focal distance %.7f (aberration %.4f h^2, spread %.2e), thick-lens formula %.7f\n",
                focus.paraxial, focus.aberration, focus.spread, expected);
    EXPECT_NEAR(focus.paraxial, expected, 5e-4 * expected);
}

}  // namespace
}  // namespace vkrt
