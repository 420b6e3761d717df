// Skins and morph targets (glTF 2.0 sections 3.7.3 and 3.7.2.2): vertices placed by their joints' matrices,
// weighted, and displaced by their targets' weights (the node's, the mesh's or an animation's), against
// positions worked out by hand; malformed skins and targets refused in one line.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "common/memory_need.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"
#include "support/gltf_document.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using nlohmann::json;

void expectNear(const glm::vec3& actual, const glm::dvec3& expected, const std::string& what) {
    EXPECT_NEAR(actual.x, expected.x, 1e-6) << what;
    EXPECT_NEAR(actual.y, expected.y, 1e-6) << what;
    EXPECT_NEAR(actual.z, expected.z, 1e-6) << what;
}

// The world corners of triangle `i` at `pose` (0: the shutter's opening), the scene's re-centring undone.
std::array<glm::dvec3, 3> corners(const Scene& scene, size_t i, int pose = 0) {
    const Triangle t = pose == 0 ? scene.triangles[i] : scene.trianglePose(static_cast<uint32_t>(i), pose);
    return {glm::dvec3(t.v0) + scene.origin, glm::dvec3(t.v1) + scene.origin,
            glm::dvec3(t.v2) + scene.origin};
}

// A triangle (0,0,0), (2,0,0), (0,1,0) with normals +x, skinned to joints A (at the origin) and B (at
// (1,0,0), turned 90 degrees about z, its inverse bind matrix the translation by -1 in x): the first corner
// on A, the second on B, the third on both with weights 0.6 and 0.2 (0.75 and 0.25 once they sum to 1). The
// skinned node is moved 100 in x, which a skin ignores; a second primitive of its mesh has no joints and
// follows the node. B turns back to 0 degrees over the one-second shutter.
test::GltfDocument skinnedTriangle() {
    test::GltfDocument d;
    const int positions = d.floats({0, 0, 0, 2, 0, 0, 0, 1, 0}, "VEC3");
    d.json["accessors"][positions]["min"] = {0, 0, 0};
    d.json["accessors"][positions]["max"] = {2, 1, 0};
    const int normals = d.floats({1, 0, 0, 1, 0, 0, 1, 0, 0}, "VEC3");
    const int joints = d.unsignedShorts({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}, "VEC4");
    const int weights = d.floats({1, 0, 0, 0, 1, 0, 0, 0, 0.6f, 0.2f, 0, 0}, "VEC4");
    const int inverseBinds = d.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0,  0, 0, 1,  // A: the identity
                                       1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1},
                                      "MAT4");
    const float half = static_cast<float>(std::sqrt(0.5));
    const int times = d.floats({0, 1}, "SCALAR");
    const int turns = d.floats({0, 0, half, half, 0, 0, 0, 1}, "VEC4");
    d.json["meshes"] = {
        {{"primitives",
          {{{"attributes",
             {{"POSITION", positions}, {"NORMAL", normals}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}},
           {{"attributes", {{"POSITION", positions}}}}}}}};
    const int a = d.node({{"name", "A"}});
    const int b = d.node({{"name", "B"}, {"translation", {1, 0, 0}}, {"rotation", {0, 0, half, half}}});
    d.json["skins"] = {{{"joints", {a, b}}, {"inverseBindMatrices", inverseBinds}}};
    d.node({{"mesh", 0}, {"skin", 0}, {"translation", {100, 0, 0}}});
    d.json["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", b}, {"path", "rotation"}}}}}},
         {"samplers", {{{"input", times}, {"output", turns}}}}}};
    d.json["scenes"][0]["extras"] = {{"shutter", {0.0, 1.0}}};
    return d;
}

TEST(Skins, VerticesFollowTheirJointsWeightedAndTheNodeTransformIsIgnored) {
    const auto file = test::temporaryFolder() / "skinned.gltf";
    skinnedTriangle().write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 2u);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    // B maps (2,0,0) to (1,1,0) and (0,1,0) to (0,-1,0); the third corner is 0.75 (0,1,0) + 0.25 (0,-1,0).
    const auto skinned = corners(scene, 0);
    expectNear(glm::vec3(skinned[0]), {0, 0, 0}, "on A alone");
    expectNear(glm::vec3(skinned[1]), {1, 1, 0}, "on B alone");
    expectNear(glm::vec3(skinned[2]), {0, 0.5, 0}, "weighted");
    // Normals turn with the joints' linear parts: +x, B's +y, and 0.75 I + 0.25 B's direction.
    const TriangleShading& shading = scene.shading[0];
    expectNear(shading.normal[0], {1, 0, 0}, "normal on A");
    expectNear(shading.normal[1], {0, 1, 0}, "normal on B");
    expectNear(shading.normal[2], glm::normalize(glm::dvec3(0.75, 0.25, 0)), "weighted normal");
    // The primitive without joints follows its node.
    const auto rigid = corners(scene, 1);
    expectNear(glm::vec3(rigid[1]), {102, 0, 0}, "rigid primitive");
    // At the shutter's close B is unturned: the skinned corners are where the mesh has them.
    ASSERT_TRUE(scene.moving());
    const auto closed = corners(scene, 0, scene.motionSegments);
    expectNear(glm::vec3(closed[1]), {2, 0, 0}, "on B at the close");
    expectNear(glm::vec3(closed[2]), {0, 1, 0}, "weighted at the close");
}

// glTF makes a skin's inverse bind matrices optional (identity matrices; tinygltf wanted them); the scene is
// centred where the joints put a skinned mesh, not where its node is (1e9 away: at that distance float
// coordinates lost the triangle); a skin's joints are counted against the memory before their matrices are
// made.
TEST(Skins, InverseBindMatricesAreOptionalAndTheJointsPlaceTheScene) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d = skinnedTriangle();
    d.json["skins"][0].erase("inverseBindMatrices");
    d.json["meshes"][0]["primitives"].erase(1);
    d.json["nodes"][2]["translation"] = {1e9, 0, 0};
    d.write(folder / "far.gltf");
    const Scene scene = loadGltf((folder / "far.gltf").string());
    ASSERT_EQ(scene.triangles.size(), 1u);
    EXPECT_LT(glm::length(scene.origin), 2.0);
    // B's matrix is now its world transform alone: (2,0,0) turns to (0,2,0) and moves to (1,2,0).
    const auto skinned = corners(scene, 0);
    expectNear(glm::vec3(skinned[0]), {0, 0, 0}, "on A alone");
    expectNear(glm::vec3(skinned[1]), {1, 2, 0}, "on B alone");
    // A skin of 10,000 joints (all A) over its 17 poses, in 100 KB: refused before its matrices are made.
    d.json["skins"][0]["joints"] = std::vector<int>(10000, 0);
    d.write(folder / "joints.gltf");
    LoadOptions small;
    small.maxSceneBytes = 100000;
    EXPECT_THROW(loadGltf((folder / "joints.gltf").string(), small), MemoryError);
    small.maxSceneBytes = 100000000;
    EXPECT_EQ(loadGltf((folder / "joints.gltf").string(), small).triangles.size(), 1u);
}

// A triangle (0,0,0), (1,0,0), (0,1,0) with normals +z and two targets: all corners up 1 in z; the third
// corner up 2 in z, its normal displaced by (1, 0, -1). The mesh's weights are (0.5, 0); placed three times:
// by a node without weights (animated to (1, 1) over the shutter), by one with (0, 1), and by one with (0.25,
// 0.5).
test::GltfDocument morphedTriangles() {
    test::GltfDocument d;
    const int positions = d.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
    d.json["accessors"][positions]["min"] = {0, 0, 0};
    d.json["accessors"][positions]["max"] = {1, 1, 0};
    const int normals = d.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int up = d.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int corner = d.floats({0, 0, 0, 0, 0, 0, 0, 0, 2}, "VEC3");
    const int tilt = d.floats({0, 0, 0, 0, 0, 0, 1, 0, -1}, "VEC3");
    const int times = d.floats({0, 1}, "SCALAR");
    const int weights = d.floats({0.5f, 0, 1, 1}, "SCALAR");
    d.json["meshes"] = {{{"primitives",
                          {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                            {"targets", {{{"POSITION", up}}, {{"POSITION", corner}, {"NORMAL", tilt}}}}}}},
                         {"weights", {0.5, 0.0}}}};
    const int animated = d.node({{"mesh", 0}});
    d.node({{"mesh", 0}, {"translation", {5, 0, 0}}, {"weights", {0.0, 1.0}}});
    d.node({{"mesh", 0}, {"translation", {10, 0, 0}}, {"weights", {0.25, 0.5}}});
    d.json["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", animated}, {"path", "weights"}}}}}},
         {"samplers", {{{"input", times}, {"output", weights}}}}}};
    d.json["scenes"][0]["extras"] = {{"shutter", {0.0, 1.0}}};
    return d;
}

TEST(MorphTargets, WeightsComeFromTheNodeElseTheMeshAndAnimationsMoveThem) {
    const auto file = test::temporaryFolder() / "morphed.gltf";
    morphedTriangles().write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 3u);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    const auto byMesh = corners(scene, 0), byNode = corners(scene, 1), blended = corners(scene, 2);
    expectNear(glm::vec3(byMesh[0]), {0, 0, 0.5}, "the mesh's weights");
    expectNear(glm::vec3(byMesh[2]), {0, 1, 0.5}, "the mesh's weights");
    expectNear(glm::vec3(byNode[0]), {5, 0, 0}, "the node's weights");
    expectNear(glm::vec3(byNode[2]), {5, 1, 2}, "the node's weights");
    expectNear(glm::vec3(blended[1]), {11, 0, 0.25}, "both targets");
    expectNear(glm::vec3(blended[2]), {10, 1, 1.25}, "both targets");
    expectNear(scene.shading[2].normal[2], glm::normalize(glm::dvec3(0.5, 0, 0.5)), "displaced normal");
    expectNear(scene.shading[2].normal[0], {0, 0, 1}, "normal left alone");
    // LINEAR weights move the corners linearly: one motion segment, exact; (1, 1) at the close.
    ASSERT_TRUE(scene.moving());
    EXPECT_EQ(scene.motionSegments, 1);
    const auto closed = corners(scene, 0, 1);
    expectNear(glm::vec3(closed[0]), {0, 0, 1}, "animated weights");
    expectNear(glm::vec3(closed[2]), {0, 1, 3}, "animated weights");
    expectNear(glm::vec3(corners(scene, 1, 1)[2]), {5, 1, 2}, "the node's weights do not move");
}

// Only the targets some node weighs are read, each counted against the memory: a target of 100,000 vertices
// (a sparse accessor of 20 bytes) takes 3.6 MB to read (a double and a float per value) beside the positions'
// 1.2 MB once weighed, nothing while no node weighs it; reading the positions alone takes 3.6 MB.
TEST(MorphTargets, OnlyWeighedTargetsAreReadAndCounted) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d;
    std::vector<float> positions(3 * 100000, 0.0f);
    for (size_t v = 0; v < 100000; ++v)
        positions[3 * v] = static_cast<float>(v % 2), positions[3 * v + 1] = static_cast<float>(v % 3);
    const int position = d.floats(positions, "VEC3");
    const int where = d.unsignedShorts({7, 0}, "SCALAR");
    const int lift = d.floats({0, 0, 1}, "VEC3");
    d.json["accessors"][where]["count"] = 1;
    json target = {
        {"count", 100000},
        {"componentType", 5126},
        {"type", "VEC3"},
        {"sparse",
         {{"count", 1},
          {"indices", {{"bufferView", d.json["accessors"][where]["bufferView"]}, {"componentType", 5123}}},
          {"values", {{"bufferView", d.json["accessors"][lift]["bufferView"]}}}}}};
    d.json["accessors"].push_back(target);
    const int sparseTarget = static_cast<int>(d.json["accessors"].size()) - 1;
    const int indices = d.unsignedShorts({0, 1, 2, 0}, "SCALAR");
    d.json["accessors"][indices]["count"] = 3;  // one triangle of the 100,000 vertices
    d.json["meshes"] = {{{"primitives",
                          {{{"attributes", {{"POSITION", position}}},
                            {"indices", indices},
                            {"targets", {{{"POSITION", sparseTarget}}}}}}},
                         {"weights", {0.0}}}};
    d.node({{"mesh", 0}});
    d.write(folder / "unweighed.gltf");
    LoadOptions small;
    small.maxSceneBytes = 4000000;
    EXPECT_NO_THROW(loadGltf((folder / "unweighed.gltf").string(), small));
    d.json["meshes"][0]["weights"] = {1.0};
    d.write(folder / "weighed.gltf");
    EXPECT_THROW(loadGltf((folder / "weighed.gltf").string(), small), MemoryError);
}

// A mesh no node skins is placed by its nodes, its JOINTS and WEIGHTS not read (malformed ones too, as before
// skins were read).
TEST(Skins, AMeshNoNodeSkinsIgnoresItsJointsAndWeights) {
    test::GltfDocument d = skinnedTriangle();
    d.json["nodes"][2].erase("skin");
    d.json["meshes"][0]["primitives"].erase(1);
    d.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
        d.floats({1, 0, 0, 0, -1, 0, 0, 0, 0.6f, 0.2f, 0, 0}, "VEC4");
    const auto file = test::temporaryFolder() / "rigid.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 1u);
    expectNear(glm::vec3(corners(scene, 0)[1]), {102, 0, 0}, "placed by its node");
}

// glTF sets no limit on a vertex's joints (section 3.7.3.2): the first test's influences spread over three
// sets, the second of them all zero, place the triangle where one set did (the third set was ignored: the
// corner it alone weighs followed the node, and the corner it shares followed its other joint alone).
TEST(Skins, EveryJointAndWeightSetIsRead) {
    test::GltfDocument d = skinnedTriangle();
    d.json["meshes"][0]["primitives"].erase(1);
    json& attributes = d.json["meshes"][0]["primitives"][0]["attributes"];
    attributes["JOINTS_0"] = d.unsignedShorts(std::vector<uint16_t>(12, 0), "VEC4");
    attributes["WEIGHTS_0"] = d.floats({1, 0, 0, 0, 0, 0, 0, 0, 0.6f, 0, 0, 0}, "VEC4");
    attributes["JOINTS_1"] = d.unsignedShorts(std::vector<uint16_t>(12, 0), "VEC4");
    attributes["WEIGHTS_1"] = d.floats(std::vector<float>(12, 0.0f), "VEC4");
    attributes["JOINTS_2"] = d.unsignedShorts({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1}, "VEC4");
    attributes["WEIGHTS_2"] = d.floats({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0.2f}, "VEC4");
    const auto file = test::temporaryFolder() / "three sets.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 1u);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    const auto skinned = corners(scene, 0);
    expectNear(glm::vec3(skinned[0]), {0, 0, 0}, "on A in the first set");
    expectNear(glm::vec3(skinned[1]), {1, 1, 0}, "on B in the third set");
    expectNear(glm::vec3(skinned[2]), {0, 0.5, 0}, "on A in the first set and B in the third");
}

// A skinned triangle whose POSITION, JOINTS_0 and WEIGHTS_0 claim a million vertices (sparse accessors of a
// few bytes): each is counted against the memory before it is read, beside what is read already. The
// positions take 36 MB to read (a double and a float per value), the joints and weights 48 MB each beside
// them and the 32 MB they are interleaved into: the skin is refused in 64 MiB (at 2^26 vertices it took 5 GB
// under --max-memory 500M) and loaded in 256 MiB; placed by a node without the skin, the mesh loads in 64.
TEST(Skins, JointsAndWeightsAreCountedAgainstTheMemoryBeforeTheyAreRead) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d;
    const size_t vertices = 1000000;
    const int positions = d.sparsePositions(vertices, {0, 1, 2}, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int joints = d.sparseOnly(vertices, {0, 1, 2}, std::vector<uint16_t>(12, 0), 5123, "VEC4");
    const int weights = d.sparseOnly(vertices, {0, 1, 2},
                                     std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 5126, "VEC4");
    const int indices = d.unsignedShorts({0, 1, 2}, "SCALAR");
    d.json["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", positions}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}},
            {"indices", indices}}}}}};
    const int joint = d.node({{"translation", {5, 0, 0}}});
    d.json["skins"] = {{{"joints", {joint}}}};
    const int skinned = d.node({{"mesh", 0}, {"skin", 0}});
    d.write(folder / "skinned.gltf");
    LoadOptions small;
    small.maxSceneBytes = 64u << 20;
    small.memorySource = "--max-memory";
    try {
        loadGltf((folder / "skinned.gltf").string(), small);
        ADD_FAILURE() << "read a million vertices' joints and weights in 64 MiB";
    } catch (const MemoryError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("mesh 0 primitive 0 JOINTS_0 would take"), std::string::npos) << message;
        EXPECT_NE(message.find("(--max-memory)"), std::string::npos) << message;
    }
    LoadOptions large;
    large.maxSceneBytes = 256u << 20;
    const Scene scene = loadGltf((folder / "skinned.gltf").string(), large);
    ASSERT_EQ(scene.triangles.size(), 1u);
    expectNear(glm::vec3(corners(scene, 0)[1]), {6, 0, 0}, "on the joint");
    d.json["nodes"][skinned].erase("skin");
    d.write(folder / "rigid.gltf");
    EXPECT_EQ(loadGltf((folder / "rigid.gltf").string(), small).triangles.size(), 1u);
}

// Malformed skins and targets: each refused with a message naming the problem.
TEST(Deformation, MalformedSkinsAndTargetsAreRefused) {
    const auto folder = test::temporaryFolder();
    struct Case {
        const char* name;
        std::function<void(test::GltfDocument&)> spoil;
        const char* expected;
    };
    const std::vector<Case> cases = {
        {"joint beyond the skin", [](test::GltfDocument& d) { d.json["skins"][0]["joints"] = {0}; },
         "refers to joint 1; the node's skin has 1"},
        {"joints without weights",
         [](test::GltfDocument& d) { d.json["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0"); },
         "JOINTS_0 and WEIGHTS_0 without the other"},
        {"negative weight",
         [](test::GltfDocument& d) {
             d.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
                 d.floats({1, 0, 0, 0, 1, 0, 0, 0, 1.5f, -0.5f, 0, 0}, "VEC4");
         },
         "negative or non-finite value at vertex 2"},
        {"too few inverse bind matrices",
         [](test::GltfDocument& d) {
             d.json["skins"][0]["inverseBindMatrices"] =
                 d.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "MAT4");
         },
         "1 inverse bind matrices for 2 joints"},
        {"skin without joints", [](test::GltfDocument& d) { d.json["skins"][0]["joints"] = json::array(); },
         "expected at least 1 item"},
        {"weights for other targets", [](test::GltfDocument& d) { d.json["nodes"][2]["weights"] = {1.0}; },
         "0 morph target(s)"},
        {"a third set without its joints",
         [](test::GltfDocument& d) {
             json& attributes = d.json["meshes"][0]["primitives"][0]["attributes"];
             attributes["JOINTS_1"] = attributes["JOINTS_0"];
             attributes["WEIGHTS_1"] = d.floats(std::vector<float>(12, 0.0f), "VEC4");
             attributes["WEIGHTS_2"] = attributes["WEIGHTS_1"];
         },
         "JOINTS_2 and WEIGHTS_2 without the other"},
        {"a set missing below the highest",
         [](test::GltfDocument& d) {
             json& attributes = d.json["meshes"][0]["primitives"][0]["attributes"];
             attributes["JOINTS_2"] = attributes["JOINTS_0"];
             attributes["WEIGHTS_2"] = d.floats(std::vector<float>(12, 0.0f), "VEC4");
         },
         "but not JOINTS_1 and WEIGHTS_1"},
    };
    for (const Case& c : cases) {
        test::GltfDocument d = skinnedTriangle();
        c.spoil(d);
        const auto file = folder / (std::string(c.name) + ".gltf");
        d.write(file);
        try {
            loadGltf(file.string());
            ADD_FAILURE() << c.name << ": loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
                << c.name << ": " << e.what();
        }
    }
    // Targets' weights: the node's must match its mesh's targets, and so must an animation's per key. Every
    // primitive of a mesh has as many targets (glTF 2.0 section 3.7.2.2).
    test::GltfDocument wrongCount = morphedTriangles();
    wrongCount.json["nodes"][1]["weights"] = {1.0, 0.0, 0.0};
    test::GltfDocument wrongKeys = morphedTriangles();
    wrongKeys.json["animations"][0]["samplers"][0]["output"] =
        wrongKeys.floats({0.5f, 0, 0, 1, 1, 0}, "SCALAR");
    test::GltfDocument unevenTargets = morphedTriangles();
    json fewerTargets = unevenTargets.json["meshes"][0]["primitives"][0];
    fewerTargets["targets"].erase(1);
    unevenTargets.json["meshes"][0]["primitives"].push_back(fewerTargets);
    for (auto& [name, d, expected] : std::vector<std::tuple<std::string, test::GltfDocument, std::string>>{
             {"node weights", wrongCount, "has 3 morph-target weight(s) for 2 morph target(s)"},
             {"animated weights", wrongKeys, "3 morph-target weight(s) per key; its mesh has 2"},
             {"uneven targets", unevenTargets,
              "mesh 0 primitive 1 has 1 morph target(s) and primitive 0 2"}}) {
        const auto file = folder / (name + ".gltf");
        d.write(file);
        try {
            loadGltf(file.string());
            ADD_FAILURE() << name << ": loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << name << ": " << e.what();
        }
    }
}

// scenes/deform.gltf: the tube's foot stays round the hip, its top turns 50 degrees about the knee; the boxy
// ball (placed first) reaches 0.6 of the way to the box of half-size 0.5, the squashed one is half as high.
TEST(Deformation, TheDeformScene) {
    const Scene scene = loadGltf((test::sourceDir() / "scenes/deform.gltf").string());
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    const glm::dvec3 foot(-0.6, 0.0, -0.5), knee = foot + glm::dvec3(0.0, 1.2, 0.0);
    const glm::dvec3 axis(-std::sin(glm::radians(50.0)), std::cos(glm::radians(50.0)), 0.0);  // the knee's
    std::vector<size_t> balls;
    double farthestAlong = 0.0;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const std::string& material = scene.materials[scene.triangles[i].material].name;
        if (material == "ball") balls.push_back(i);
        if (material != "tube") continue;
        // Below 0.9 the hip's corners, round the upright axis; from 0.3 along the knee's turned axis, the
        // knee's, within the tube's radius of it (the blend between bends the tube less than either).
        for (const glm::dvec3& p : corners(scene, i)) {
            const double along = glm::dot(p - knee, axis);
            if (p.y < 0.9) {
                EXPECT_NEAR(glm::length(glm::dvec2(p.x - foot.x, p.z - foot.z)), 0.22, 1e-5);
            }
            if (along > 0.3 + 1e-6) {
                EXPECT_LE(glm::length(p - knee - along * axis), 0.22 + 1e-5);
                farthestAlong = std::max(farthestAlong, along);
            }
        }
    }
    EXPECT_NEAR(farthestAlong, 1.2, 1e-5);  // the top cap
    ASSERT_EQ(balls.size() % 2, 0u);
    double boxyBottom = 1e9, squashedTop = 0.0;
    for (size_t k = 0; k < balls.size(); ++k) {
        for (const glm::dvec3& p : corners(scene, balls[k])) {
            if (k < balls.size() / 2)
                boxyBottom = std::min(boxyBottom, p.y);
            else
                squashedTop = std::max(squashedTop, p.y);
        }
    }
    // The boxy ball's pole moves 0.6 of the way from 0.55 to 0.5 below its centre at 0.55; the squashed
    // ball's from 0.55 to 0.275 above its centre at 0.275.
    EXPECT_NEAR(boxyBottom, 0.55 - (0.55 + 0.6 * (0.5 - 0.55)), 1e-5);
    EXPECT_NEAR(squashedTop, 0.275 + 0.275, 1e-5);
}

}  // namespace
}  // namespace vkrt
