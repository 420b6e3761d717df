// Loading real glTF files: every third-party scene loads (or names what it lacks), with counts checked.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <set>
#include <utility>

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <nlohmann/json.hpp>

#include "common/memory_need.h"
#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/mipmaps.h"
#include "scene/scene_error.h"
#include "scene/shading_inputs.h"
#include "scene/tangent_frames.h"
#include "support/gltf_document.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"
#include "texture_sampling.h"

namespace vkrt {
namespace {

Scene loadReal(const std::string& relative) {
    return loadGltf((test::scenesReal() / relative).string());
}

#define REQUIRE_SCENES_REAL() \
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal()

TEST(GltfLoader, EveryThirdPartySceneLoads) {
    REQUIRE_SCENES_REAL();
    const auto files = test::gltfFilesUnder(test::scenesReal());
    ASSERT_GE(files.size(), 15u);
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        try {
            const Scene scene = loadGltf(file.string());
            EXPECT_FALSE(scene.triangles.empty());
            EXPECT_EQ(scene.triangles.size(), scene.shading.size());
            EXPECT_FALSE(scene.bounds.empty());
            for (const Triangle& t : scene.triangles) ASSERT_LT(t.material, scene.materials.size());
        } catch (const SceneError& e) {
            // Allowed only when the file needs something vkrt names as unsupported.
            EXPECT_NE(std::string(e.what()).find("does not support"), std::string::npos) << e.what();
        }
    }
}

TEST(GltfLoader, VkrtSphereIsPlacedByItsNodeTransform) {
    // A sphere of radius 0.5 under a parent that scales by 2 and translates, declared required.
    const std::filesystem::path file = test::temporaryFolder() / "spheres.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "extensionsRequired": ["VKRT_sphere"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "materials": [{"name": "a"}, {"name": "lamp", "emissiveFactor": [1, 1, 1]}],
        "nodes": [
            {"translation": [10, 0, 0], "scale": [2, 2, 2], "children": [1, 2]},
            {"translation": [0, 1, 0], "extensions": {"VKRT_sphere": {"radius": 0.5, "material": 1}}},
            {"extensions": {"VKRT_sphere": {"radius": 0.25}}}
        ]})");
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.spheres.size(), 2u);
    EXPECT_TRUE(scene.triangles.empty());
    const glm::dvec3 first = glm::dvec3(scene.spheres[0].center) + scene.origin;
    EXPECT_NEAR(first.x, 10.0, 1e-5);
    EXPECT_NEAR(first.y, 2.0, 1e-5);
    EXPECT_NEAR(first.z, 0.0, 1e-5);
    EXPECT_FLOAT_EQ(scene.spheres[0].radius, 1.0f);
    EXPECT_EQ(scene.spheres[0].material, 1u);
    EXPECT_FLOAT_EQ(scene.spheres[1].radius, 0.5f);
    EXPECT_EQ(scene.materials[scene.spheres[1].material].name, "default");
    EXPECT_EQ(scene.emissiveSpheres, std::vector<uint32_t>{0});
    EXPECT_EQ(scene.primitiveCount(), 2u);
    EXPECT_TRUE(scene.isSphere(0));
    // The bounds hold both spheres.
    EXPECT_NEAR(scene.bounds.max.y + scene.origin.y, 3.0, 1e-4);
    EXPECT_NEAR(scene.bounds.min.y + scene.origin.y, -0.5, 1e-4);
}

TEST(GltfLoader, MaterialExtensionsAndTextureSlotsAreRead) {
    // KHR_materials_specular (factors and a transformed specular colour texture), an occlusion texture with its
    // strength and a transformed metallic-roughness texture; the image is a 1x1 PNG in a data URI.
    const std::filesystem::path file = test::temporaryFolder() / "materials.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_texture_transform", "VKRT_sphere"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="}],
        "textures": [{"source": 0}],
        "materials": [{
            "pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0,
                "extensions": {"KHR_texture_transform": {"scale": [2, 3], "rotation": 0.5, "offset": [0.25, 0]}}}},
            "occlusionTexture": {"index": 0, "strength": 0.5, "texCoord": 1},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.25, "specularColorFactor": [1, 0.5, 0],
                "specularColorTexture": {"index": 0,
                    "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.5]}}}}}
        }],
        "nodes": [{"extensions": {"VKRT_sphere": {"radius": 1, "material": 0}}}]
    })");
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.materials.size(), 1u);
    const Material& m = scene.materials[0];
    EXPECT_EQ(m.metallicRoughnessTexture.texture, 0);
    EXPECT_EQ(m.metallicRoughnessTexture.scale, glm::vec2(2.0f, 3.0f));
    EXPECT_FLOAT_EQ(m.metallicRoughnessTexture.rotation, 0.5f);
    EXPECT_EQ(m.metallicRoughnessTexture.offset, glm::vec2(0.25f, 0.0f));
    EXPECT_EQ(m.occlusionTexture.texture, 0);
    EXPECT_FLOAT_EQ(m.occlusionStrength, 0.5f);
    EXPECT_EQ(m.occlusionTexture.texCoord, 1);  // the second set is read, without a warning
    EXPECT_FLOAT_EQ(m.specularFactor, 0.25f);
    EXPECT_EQ(m.specularColor, glm::vec3(1.0f, 0.5f, 0.0f));
    EXPECT_EQ(m.specularColorTexture.texture, 0);
    EXPECT_EQ(m.specularColorTexture.offset, glm::vec2(0.5f, 0.5f));
    EXPECT_FALSE(m.specularTexture.used());
    EXPECT_FALSE(m.baseColorTexture.used());
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
}

// A file of one sphere whose base colour is the PNG `png` (base64) in a data URI.
std::filesystem::path texturedSphere(const std::string& name, const std::string& png) {
    const std::filesystem::path file = test::temporaryFolder() / (name + ".gltf");
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0, "scenes": [{"nodes": [0]}],
        "images": [{"uri": "data:image/png;base64,)" +
                              png + R"("}],
        "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "nodes": [{"extensions": {"VKRT_sphere": {"radius": 1, "material": 0}}}]
    })");
    return file;
}

TEST(GltfLoader, SixteenBitImagesRoundToTheNearestEightBitValue) {
    // A 2 x 1 grey PNG of 16 bits a channel: 0xff00 (254.0 of 255) and 0x01ff (1.99 of 255). Textures keep 8
    // bits a channel: 254 and 2, where the values' high bytes were 255 and 1.
    const Scene scene = loadGltf(texturedSphere("sixteen",
                                                "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABEAAAAACB2fwVAAAADUlEQVR4nGP4"
                                                "z8D4HwAFAgIAv90bWgAAAABJRU5ErkJggg==")
                                     .string());
    ASSERT_EQ(scene.textures.size(), 1u);
    const Texture& texture = scene.textures[0];
    ASSERT_EQ(texture.width, 2);
    ASSERT_TRUE(texture.rgba);
    ASSERT_GE(texture.rgba->size(), 8u);
    const std::vector<uint8_t> expected = {254, 254, 254, 255, 2, 2, 2, 255};
    EXPECT_EQ(std::vector<uint8_t>(texture.rgba->begin(), texture.rgba->begin() + 8), expected);
}

// A file of one sphere of material 0 among `materials`, over `textures` and the PNG images `images` (files
// written beside it: each name's side in texels, a grey checker), with `extensionsUsed`.
std::filesystem::path texturedSphereFile(const std::string& name, const nlohmann::json& materials,
                                         const nlohmann::json& textures,
                                         const std::vector<std::pair<std::string, int>>& images,
                                         nlohmann::json extensionsUsed = nlohmann::json::array()) {
    const std::filesystem::path folder = test::temporaryFolder();
    nlohmann::json imageList = nlohmann::json::array();
    for (const auto& [uri, side] : images) {
        if (uri.rfind("data:", 0) == 0) {
            imageList.push_back({{"uri", uri}});
            continue;
        }
        std::vector<uint8_t> grey(static_cast<size_t>(side) * side);
        for (size_t i = 0; i < grey.size(); ++i) grey[i] = ((i % side + i / side) % 2) != 0 ? 200 : 50;
        EXPECT_TRUE(stbi_write_png((folder / uri).string().c_str(), side, side, 1, grey.data(), side));
        imageList.push_back({{"uri", uri}});
    }
    extensionsUsed.push_back("VKRT_sphere");
    const nlohmann::json document = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", extensionsUsed},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"images", imageList},
        {"textures", textures},
        {"materials", materials},
        {"nodes", {{{"extensions", {{"VKRT_sphere", {{"radius", 1}, {"material", 0}}}}}}}}};
    const std::filesystem::path file = folder / (name + ".gltf");
    test::writeText(file, document.dump());
    return file;
}

// Only the textures a slot vkrt reads uses are decoded, packed and counted: a texture no material names, and
// one named only by an extension vkrt ignores (64 x 64 PNGs), took 2 x 21844 bytes of packed texels beside
// the 2 x 2 base colour's (a 1024 x 1024 one took 5.6 MB in a scene whose material used no texture, and 40 of
// them had the GPU refuse a scene for needing 875 MiB). The used texture, listed last, is the scene's first.
TEST(GltfLoader, TexturesNoSlotReadsAreNotDecodedOrPacked) {
    const nlohmann::json baseColour = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    const Scene alone =
        loadGltf(texturedSphereFile("alone", nlohmann::json::array({baseColour}),
                                    nlohmann::json::array({{{"source", 0}}}), {{"used.png", 2}})
                     .string());
    ASSERT_EQ(alone.textures.size(), 1u);

    nlohmann::json withOthers = {
        {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 2}}}}},
        {"extensions", {{"KHR_materials_iridescence", {{"iridescenceTexture", {{"index", 1}}}}}}}};
    const Scene scene =
        loadGltf(texturedSphereFile("others", nlohmann::json::array({withOthers}),
                                    {{{"source", 0}}, {{"source", 1}}, {{"source", 2}}},
                                    {{"unused.png", 64}, {"ignored.png", 64}, {"used.png", 2}},
                                    nlohmann::json::array({"KHR_materials_iridescence"}))
                     .string());
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].width, 2);
    EXPECT_EQ(scene.materials[0].baseColorTexture.texture, 0);
    EXPECT_EQ(packedTextureBytes(scene), packedTextureBytes(alone));
    EXPECT_EQ(packedTextureBytes(scene), (4u + 1u) * 4u);
}

// Only the materials the rendered scene places have their textures read: the textures of a material no node
// uses, and of one placed only in another scene, are not decoded or packed, and an image of theirs that does
// not decode fails nothing (a 1024 x 1024 texture of an unused material took 5.6 MB of GPU memory, and a
// missing one failed the load). Every material keeps its index; one placed through a child node's VKRT_shape
// has its texture.
TEST(GltfLoader, TexturesOfMaterialsNoPlacedSurfaceUsesAreNotRead) {
    const auto baseColour = [](int texture) {
        return nlohmann::json{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", texture}}}}}};
    };
    const std::filesystem::path file = texturedSphereFile(
        "unplaced", {baseColour(0), baseColour(1), baseColour(2), baseColour(3)},
        {{{"source", 0}}, {{"source", 1}}, {{"source", 2}}, {{"source", 3}}},
        {{"placed.png", 2}, {"unused.png", 64}, {"data:image/png;base64,AAAA", 0}, {"child.png", 4}},
        nlohmann::json::array({"VKRT_shape"}));
    nlohmann::json document = nlohmann::json::parse(test::readText(file));
    document["nodes"][0]["children"] = {1};
    document["nodes"].push_back({{"extensions", {{"VKRT_shape", {{"shape", "box"}, {"material", 3}}}}}});
    document["nodes"].push_back({{"extensions", {{"VKRT_sphere", {{"radius", 1}, {"material", 2}}}}}});
    document["scenes"].push_back({{"nodes", {2}}});
    test::writeText(file, document.dump());

    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.materials.size(), 4u);
    ASSERT_EQ(scene.textures.size(), 2u);
    EXPECT_EQ(scene.textures[scene.materials[0].baseColorTexture.texture].width, 2);
    EXPECT_EQ(scene.textures[scene.materials[3].baseColorTexture.texture].width, 4);
    EXPECT_FALSE(scene.materials[1].baseColorTexture.used());
    EXPECT_FALSE(scene.materials[2].baseColorTexture.used());
    EXPECT_EQ(packedTextureBytes(scene), (4u + 1u + 16u + 4u + 1u) * 4u);

    // The other scene chosen, its sphere's material is read, and its image fails as it should.
    document["scene"] = 1;
    test::writeText(file, document.dump());
    try {
        loadGltf(file.string());
        FAIL() << "the undecodable image of a placed material was accepted";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("material 2"), std::string::npos) << e.what();
    }
}

// Textures that show one image share its decoded texels and, where they read it in one colour space, its
// packed texels: each texture was given its own RGBA copy and mipmaps (41 textures of one 2048 x 2048 PNG in
// a 32 KB file took 711 MB). Four base colour textures of one 64 x 64 image, each with its own sampler, and a
// metallic-roughness slot reading one of them as data: one copy in sRGB, one linear.
TEST(GltfLoader, TexturesOfOneImageShareTheirTexels) {
    nlohmann::json materials = nlohmann::json::array();
    nlohmann::json textures = nlohmann::json::array();
    for (int i = 0; i < 4; ++i) {
        materials.push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
        textures.push_back({{"source", 0}, {"sampler", i}});
    }
    materials[0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
    const std::filesystem::path file =
        texturedSphereFile("shared", materials, textures, {{"shared.png", 64}});
    // Repeat (trilinear), clamped, nearest without mipmaps, mirrored.
    nlohmann::json document = nlohmann::json::parse(test::readText(file));
    document["samplers"] = {nlohmann::json::object(),
                            {{"wrapS", 33071}, {"wrapT", 33071}},
                            {{"magFilter", 9728}, {"minFilter", 9728}},
                            {{"wrapS", 33648}}};
    for (int i = 1; i < 4; ++i) {  // each material placed, so read
        document["nodes"].push_back({{"extensions", {{"VKRT_sphere", {{"radius", 1}, {"material", i}}}}}});
        document["scenes"][0]["nodes"].push_back(i);
    }
    test::writeText(file, document.dump());
    const Scene scene = loadGltf(file.string());
    const size_t copy = (64u * 64u + mipmapChainTexels(64, 64)) * 4u;
    EXPECT_EQ(packedTextureBytes(scene), 2 * copy);
    const PackedTextures packed = packTextures(scene);
    ASSERT_EQ(packed.texels.size() * 4, 2 * copy);
    // Each texture keeps its sampler; the sRGB ones read the same texels.
    std::set<uint32_t> flags, colourTexels;
    for (int i = 0; i < 4; ++i) {
        const gpu::GpuTexture& t = packed.textures[scene.materials[i].baseColorTexture.texture];
        flags.insert(t.flags);
        colourTexels.insert(t.firstTexel);
    }
    EXPECT_EQ(flags.size(), 4u);
    EXPECT_EQ(colourTexels.size(), 1u);
}

// KHR_materials_volume's thicknessTexture is checked and never read (a ray tracer measures the thickness):
// an image that does not decode, or a texture with only a KTX2 image, failed the whole load there. A texture
// that does not exist still fails.
TEST(GltfLoader, ThicknessTextureIsCheckedAndNotRead) {
    const nlohmann::json volume = {
        {"extensions",
         {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
          {"KHR_materials_volume", {{"thicknessFactor", 0.1}, {"thicknessTexture", {{"index", 0}}}}}}}};
    const nlohmann::json used = {"KHR_materials_transmission", "KHR_materials_volume", "KHR_texture_basisu"};
    const std::string garbage =
        "data:image/png;base64," + test::base64({'n', 'o', 't', ' ', 'a', 'n', ' ', 'i'});
    const std::string ktx2 =
        "data:image/ktx2;base64," + test::base64({0xab, 'K', 'T', 'X', ' ', '2', '0', 0xbb});
    const nlohmann::json basisu = {{"extensions", {{"KHR_texture_basisu", {{"source", 0}}}}}};
    for (const auto& [texture, uri] :
         {std::pair{nlohmann::json{{"source", 0}}, garbage}, std::pair{basisu, ktx2}}) {
        SCOPED_TRACE(uri);
        const Scene scene = loadGltf(texturedSphereFile("thickness", nlohmann::json::array({volume}),
                                                        nlohmann::json::array({texture}), {{uri, 0}}, used)
                                         .string());
        EXPECT_TRUE(scene.materials[0].hasVolume());
    }
    nlohmann::json missing = volume;
    missing["extensions"]["KHR_materials_volume"]["thicknessTexture"]["index"] = 1;
    EXPECT_THROW(loadGltf(texturedSphereFile("missing", nlohmann::json::array({missing}),
                                             nlohmann::json::array({{{"source", 0}}}), {{garbage, 0}}, used)
                              .string()),
                 SceneError);
}

TEST(GltfLoader, AttenuationDistanceBelowFloatsRangeAbsorbsAll) {
    // 1e-50 is positive, and rounds to 0 in single precision: it absorbs as float's smallest distance does
    // (all light over any path). It was refused as "attenuationDistance must be positive". 0 and negative
    // ones are.
    for (const char* distance : {"1e-50", "0", "-1"}) {
        SCOPED_TRACE(distance);
        const std::filesystem::path file = test::temporaryFolder() / "tiny-distance.gltf";
        test::writeText(file, std::string(R"({
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "VKRT_sphere"],
            "scene": 0, "scenes": [{"nodes": [0]}],
            "materials": [{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                "KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": )") +
                                  distance + R"(}}}],
            "nodes": [{"extensions": {"VKRT_sphere": {"radius": 1, "material": 0}}}]})");
        if (std::string(distance) == "1e-50") {
            const Scene scene = loadGltf(file.string());
            EXPECT_EQ(scene.materials[0].attenuationDistance, std::numeric_limits<float>::denorm_min());
        } else {
            EXPECT_THROW(loadGltf(file.string()), SceneError);
        }
    }
}

TEST(GltfLoader, CoatNormalTextureOnAnotherTexCoordSetIsWarnedAbout) {
    // One tangent frame a vertex, from the texture coordinates the base's normal texture reads: a clearcoat
    // normal texture on the other set is mapped with it, and the loader says so; on the same set, nothing.
    // The sphere's normal texture is not transformed, so it says nothing of that.
    for (const int coatSet : {0, 1}) {
        SCOPED_TRACE(coatSet);
        const std::filesystem::path file = test::temporaryFolder() / "coat.gltf";
        test::writeText(file, R"({
            "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_clearcoat", "VKRT_sphere"],
            "scene": 0, "scenes": [{"nodes": [0]}],
            "images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="}],
            "textures": [{"source": 0}],
            "materials": [{"normalTexture": {"index": 0},
                "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
                    "clearcoatNormalTexture": {"index": 0, "texCoord": )" +
                                  std::to_string(coatSet) + R"(}}}}],
            "nodes": [{"extensions": {"VKRT_sphere": {"radius": 1, "material": 0}}}]
        })");
        const Scene scene = loadGltf(file.string());
        if (coatSet == 0) {
            EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
        } else {
            ASSERT_EQ(scene.warnings.size(), 1u);
            EXPECT_NE(scene.warnings[0].find(
                          "material 0: the normal texture reads TEXCOORD_0 and the clearcoat normal "
                          "texture TEXCOORD_1; vkrt maps both with the tangent frame of the first"),
                      std::string::npos)
                << scene.warnings[0];
        }
    }
}

TEST(GltfLoader, NormalTexturesTurnedWhereNoFrameFollowsAreWarnedAbout) {
    // A clearcoat normal texture turned otherwise than the base's is mapped with the base's frame: the loader
    // says so. A uniform scale and an offset move no frame, and say nothing; nor does a sphere's normal
    // texture turned or mirrored alike with its coat's, whose frame follows the transform (it did not, and
    // was warned about, until 2026-12-07).
    const auto load = [](const std::string& baseTransform, const std::string& coatTransform) {
        const std::filesystem::path file = test::temporaryFolder() / "turned-coat.gltf";
        test::writeText(file, R"({
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_materials_clearcoat", "KHR_texture_transform", "VKRT_sphere"],
            "scene": 0, "scenes": [{"nodes": [0]}],
            "images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="}],
            "textures": [{"source": 0}],
            "materials": [{"normalTexture": {"index": 0, "extensions": {"KHR_texture_transform": )" +
                                  baseTransform + R"(}},
                "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
                    "clearcoatNormalTexture": {"index": 0, "extensions": {"KHR_texture_transform": )" +
                                  coatTransform + R"(}}}}}],
            "nodes": [{"extensions": {"VKRT_sphere": {"radius": 1, "material": 0}}}]
        })");
        return loadGltf(file.string()).warnings;
    };
    EXPECT_TRUE(load(R"({"scale": [2, 2], "offset": [0.5, 0]})", "{}").empty());
    const std::vector<std::string> coat = load("{}", R"({"rotation": 0.9})");
    ASSERT_EQ(coat.size(), 1u);
    EXPECT_NE(coat[0].find("material 0: KHR_texture_transform turns, mirrors or stretches the normal texture "
                           "and the clearcoat normal texture differently"),
              std::string::npos)
        << coat[0];
    EXPECT_TRUE(load(R"({"scale": [-1, 1]})", R"({"scale": [-1, 1]})").empty());
    EXPECT_TRUE(load(R"({"rotation": 0.9})", R"({"rotation": 0.9})").empty());
}

TEST(GltfLoader, VertexColorsFollowTheirTriangles) {
    // scenes/textures.gltf: a floor without COLOR_0, then a tile with red, green, blue and white corners.
    const Scene scene = loadGltf((test::sourceDir() / "scenes/textures.gltf").string());
    ASSERT_EQ(scene.vertexColors.size(), scene.triangles.size());
    int white = 0, coloured = 0;
    for (const auto& corners : scene.vertexColors) {
        bool allWhite = true;
        for (const glm::vec4& c : corners) {
            allWhite = allWhite && c == glm::vec4(1.0f);
            EXPECT_EQ(c.a, 1.0f);  // RGB colours get alpha 1
        }
        allWhite ? ++white : ++coloured;
    }
    EXPECT_EQ(white, 2);     // the floor
    EXPECT_EQ(coloured, 2);  // the tile
    const auto& tile = scene.vertexColors.back();
    bool red = false;
    for (const glm::vec4& c : tile) red = red || (std::abs(c.r - 1.0f) < 1e-6f && std::abs(c.g - 0.1f) < 1e-6f);
    EXPECT_TRUE(red);
}

TEST(GltfLoader, TangentFramesFollowTextureCoordinatesAndNodes) {
    // scenes/surfaces.gltf: two normal-mapped panels facing +z whose u grows along their local +x and v down
    // them. One derives its tangents; the other gives TANGENT (+x, w 1) and is mirrored in x by its node. In
    // the world, the tangent points where u grows (+x, then -x) and the bitangent w cross(n, t) points up the
    // image (+y) on both; triangles without a normal map have no frame.
    const Scene scene = loadGltf((test::sourceDir() / "scenes/surfaces.gltf").string());
    ASSERT_EQ(scene.tangents.size(), scene.triangles.size());
    int derived = 0, mirrored = 0;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const Material& material = scene.materials[scene.triangles[i].material];
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 frame = scene.tangents[i][k];
            if (!material.normalTexture.used()) {
                EXPECT_EQ(frame, glm::vec4(0.0f));
                continue;
            }
            const glm::vec3 normal = scene.shading[i].normal[k];
            const glm::vec3 bitangent = frame.w * glm::cross(normal, glm::vec3(frame));
            EXPECT_NEAR(bitangent.y, 1.0f, 1e-6f);
            const bool left = scene.triangles[i].v0.x + scene.origin.x < -0.8;
            EXPECT_NEAR(frame.x, left ? 1.0f : -1.0f, 1e-6f);
            EXPECT_EQ(frame.w, left ? 1.0f : -1.0f);
            (left ? derived : mirrored) += k == 0;
        }
    }
    EXPECT_EQ(derived, 2);
    EXPECT_EQ(mirrored, 2);
}

// Texture 0 of `d`: an image of one texel (a flat normal, read as any other colour).
void addOneTexelTexture(test::GltfDocument& d) {
    d.json["images"] = {{{"uri",
                          "data:image/png;base64,"
                          "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAA"
                          "BJRU5ErkJggg=="}}};
    d.json["textures"] = {{{"source", 0}}};
}

TEST(GltfLoader, DerivedTangentFramesSplitAtAMirroredSeam) {
    // Two squares side by side facing +z, sharing the seam's two vertices (x = 1), the right one's texture
    // mirrored across it (u = 2 - x; v down both): each triangle's frame is its own half's, at the seam too:
    // tangent +x and w 1 on the left, -x and -1 on the right, the bitangent up (+y) on both. Averaged over
    // the seam's vertices, the two tangents cancelled there and left what rounding gave.
    test::GltfDocument d;
    const int positions = d.positions({0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0});
    const int normals = d.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int uvs = d.floats({0, 1, 1, 1, 0, 1, 0, 0, 1, 0, 0, 0}, "VEC2");
    const int indices = d.unsignedShorts({0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4}, "SCALAR");
    addOneTexelTexture(d);
    d.json["materials"] = {{{"normalTexture", {{"index", 0}}}}};
    d.json["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
            {"indices", indices},
            {"material", 0}}}}}};
    d.node({{"mesh", 0}});
    const std::filesystem::path file = test::temporaryFolder() / "seam.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.tangents.size(), 4u);
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        const bool left = (t.v0.x + t.v1.x + t.v2.x) / 3.0f + scene.origin.x < 1.0f;
        SCOPED_TRACE(left ? "left" : "right");
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 frame = scene.tangents[i][k];
            EXPECT_LT(glm::length(glm::vec3(frame) - glm::vec3(left ? 1.0f : -1.0f, 0.0f, 0.0f)), 1e-6f);
            EXPECT_EQ(frame.w, left ? 1.0f : -1.0f);
            const glm::vec3 bitangent = frame.w * glm::cross(scene.shading[i].normal[k], glm::vec3(frame));
            EXPECT_LT(glm::length(bitangent - glm::vec3(0.0f, 1.0f, 0.0f)), 1e-6f);
        }
    }
}

TEST(GltfLoader, DerivedTangentFramesFollowAMorphTargetsTurn) {
    // A square facing +z, u growing along +x, with a normal texture and no TANGENT, which one morph target at
    // weight 1 turns 90 degrees about +y (its positions and normals displaced: +x goes to -z, +z to +x). The
    // frames are derived from the mesh as the target leaves it: tangent -z, the bitangent still up. From the
    // unmorphed mesh the tangent stayed +x, and the normal texture was lit as if the square had not turned.
    test::GltfDocument d;
    const int positions = d.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    const int normals = d.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int uvs = d.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
    const int indices = d.unsignedShorts({0, 1, 2, 0, 2, 3}, "SCALAR");
    const int turnedPositions = d.positions({0, 0, 0, -1, 0, -1, -1, 0, -1, 0, 0, 0});
    const int turnedNormals = d.floats({1, 0, -1, 1, 0, -1, 1, 0, -1, 1, 0, -1}, "VEC3");
    addOneTexelTexture(d);
    d.json["materials"] = {{{"normalTexture", {{"index", 0}}}}};
    d.json["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
            {"targets", {{{"POSITION", turnedPositions}, {"NORMAL", turnedNormals}}}},
            {"indices", indices},
            {"material", 0}}}},
         {"weights", {1.0}}}};
    d.node({{"mesh", 0}});
    const std::filesystem::path file = test::temporaryFolder() / "morphed-tangents.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.tangents.size(), 2u);
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 frame = scene.tangents[i][k];
            EXPECT_LT(glm::length(glm::vec3(frame) - glm::vec3(0.0f, 0.0f, -1.0f)), 1e-6f) << i << " " << k;
            EXPECT_LT(glm::length(scene.shading[i].normal[k] - glm::vec3(1.0f, 0.0f, 0.0f)), 1e-6f);
            const glm::vec3 bitangent = frame.w * glm::cross(scene.shading[i].normal[k], glm::vec3(frame));
            EXPECT_LT(glm::length(bitangent - glm::vec3(0.0f, 1.0f, 0.0f)), 1e-6f);
        }
    }
}

TEST(GltfLoader, DerivedTangentFramesFollowTheNormalTexturesTransform) {
    // Three squares facing +z whose u grows along +x and v down them (glTF's v grows down the image), each
    // with a normal texture and derived tangents: as they are, turned by 90 degrees by KHR_texture_transform
    // (u' = v, v' = -u: the image's +u runs down the square) and mirrored by it (u' = -u). The frame is the
    // image's: the tangent points where u' grows and the bitangent w cross(n, t) up the image (where v'
    // falls). Taken from the mesh's coordinates alone, the mirrored normal map showed its ridges as valleys.
    test::GltfDocument d;
    const int positions = d.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3");
    d.json["accessors"][positions]["min"] = {0, 0, 0};
    d.json["accessors"][positions]["max"] = {1, 1, 0};
    const int normals = d.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int uvs = d.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
    const int indices = d.unsignedShorts({0, 1, 2, 0, 2, 3}, "SCALAR");
    addOneTexelTexture(d);
    d.json["extensionsUsed"] = {"KHR_texture_transform"};
    const nlohmann::json transforms[] = {
        nlohmann::json::object(), {{"rotation", M_PI / 2}}, {{"scale", {-1, 1}}}};
    for (int m = 0; m < 3; ++m) {
        nlohmann::json normalTexture = {{"index", 0}};
        if (!transforms[m].empty()) normalTexture["extensions"] = {{"KHR_texture_transform", transforms[m]}};
        d.json["materials"].push_back({{"normalTexture", normalTexture}});
        d.json["meshes"].push_back(
            {{"primitives",
              {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
                {"indices", indices},
                {"material", m}}}}});
        d.node({{"mesh", m}, {"translation", {2.0 * m, 0.0, 0.0}}});
    }
    const std::filesystem::path file = test::temporaryFolder() / "turned.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.tangents.size(), 6u);
    const glm::vec3 tangents[] = {{1, 0, 0}, {0, -1, 0}, {-1, 0, 0}};
    const glm::vec3 bitangents[] = {{0, 1, 0}, {1, 0, 0}, {0, 1, 0}};
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const uint32_t m = scene.triangles[i].material;
        SCOPED_TRACE(m);
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 frame = scene.tangents[i][k];
            const glm::vec3 bitangent = frame.w * glm::cross(scene.shading[i].normal[k], glm::vec3(frame));
            EXPECT_LT(glm::length(glm::vec3(frame) - tangents[m]), 1e-6f);
            EXPECT_LT(glm::length(bitangent - bitangents[m]), 1e-6f);
        }
    }
}

TEST(TangentFrames, MirroredTextureCoordinatesFlipTheHandedness) {
    // A square in the xy plane facing +z: with u along +x and v down (-y) the frame is right-handed (w = 1,
    // bitangent +y); with u along -x it is mirrored (tangent -x, w = -1, the bitangent still +y). Texture
    // coordinates that give no direction give no frame.
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<std::array<uint32_t, 3>> faces = {{0, 1, 2}, {0, 2, 3}};
    for (const float direction : {1.0f, -1.0f}) {
        std::vector<float> uvs;
        for (size_t v = 0; v < 4; ++v) {
            uvs.push_back(direction * positions[3 * v]);
            uvs.push_back(1.0f - positions[3 * v + 1]);
        }
        const VertexTangents derived = vertexTangents(positions, normals, uvs, faces);
        EXPECT_EQ(derived.mirroredFaces, std::vector<bool>(2, direction < 0.0f));
        const std::vector<float>& tangents = direction > 0.0f ? derived.frames : derived.mirroredFrames;
        EXPECT_EQ(derived.frames, derived.mirroredFrames);  // one kind of face: both frames are its
        for (size_t v = 0; v < 4; ++v) {
            EXPECT_NEAR(tangents[4 * v], direction, 1e-6f);
            EXPECT_NEAR(tangents[4 * v + 1], 0.0f, 1e-6f);
            EXPECT_EQ(tangents[4 * v + 3], direction);
        }
    }
    const std::vector<float> flat(8, 0.5f);
    const VertexTangents none = vertexTangents(positions, normals, flat, faces);
    for (float t : none.frames) EXPECT_EQ(t, 0.0f);
    for (float t : none.mirroredFrames) EXPECT_EQ(t, 0.0f);
    EXPECT_EQ(faceTangent({glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)},
                          {glm::dvec2(0, 1), glm::dvec2(1, 1), glm::dvec2(0, 0)}, glm::dvec3(0, 0, 1)),
              glm::vec4(1, 0, 0, 1));
}

// A texture's texels, as the loader shares them.
std::shared_ptr<const std::vector<uint8_t>> texels(std::vector<uint8_t> rgba) {
    return std::make_shared<const std::vector<uint8_t>>(std::move(rgba));
}

TEST(Mipmaps, EveryTexelCountsAndColoursAverageAsLight) {
    // A 3x1 row of linear data (0, 255, 0) halves to one texel of their mean, 85: the odd texel is not
    // dropped. A 2x2 black-and-white checker of sRGB colours halves to 188, the sRGB code of linear 0.5;
    // its alpha (255 everywhere) stays 255. Levels go down to 1x1.
    Texture row;
    row.width = 3;
    row.height = 1;
    row.rgba = texels({0, 0, 0, 0, 255, 255, 255, 255, 0, 0, 0, 0});
    const std::vector<TextureLevel> rowLevels = mipmapChain(row, false);
    ASSERT_EQ(rowLevels.size(), 1u);
    EXPECT_EQ(rowLevels[0].width, 1);
    EXPECT_EQ(rowLevels[0].rgba[0], 85);
    EXPECT_EQ(rowLevels[0].rgba[3], 85);
    Texture checker;
    checker.width = checker.height = 2;
    checker.rgba = texels({255, 255, 255, 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 255});
    const std::vector<TextureLevel> levels = mipmapChain(checker, true);
    ASSERT_EQ(levels.size(), 1u);
    EXPECT_EQ(levels[0].rgba[0], 188);
    EXPECT_EQ(levels[0].rgba[3], 255);
    checker.width = 4;
    checker.height = 1;
    EXPECT_EQ(mipmapChain(checker, true).size(), 2u);  // 2x1, then 1x1
}

TEST(Mipmaps, SrgbCodesAreTheFormulasForEveryPairOfBytes) {
    // Every pair (a, b) of sRGB codes averaged, as a 2x2 box of two columns a and b: the level's code is the
    // one the formula gives for the mean in linear light (mipmaps.cpp encodes by a table search, the formula
    // deciding near each boundary). Linear data (alpha) rounds its mean, halves up.
    Texture pairs;
    pairs.width = pairs.height = 512;
    std::vector<uint8_t> rgba(512 * 512 * 4);
    for (int y = 0; y < 512; ++y) {
        for (int x = 0; x < 512; ++x) {
            const uint8_t value = static_cast<uint8_t>(x % 2 == 0 ? x / 2 : y / 2);
            uint8_t* texel = &rgba[(static_cast<size_t>(y) * 512 + x) * 4];
            texel[0] = texel[3] = value;
            texel[1] = texel[2] = static_cast<uint8_t>(255 - value);
        }
    }
    pairs.rgba = texels(std::move(rgba));
    const std::vector<TextureLevel> levels = mipmapChain(pairs, true);
    ASSERT_EQ(levels[0].width, 256);
    auto expected = [](int a, int b) {
        const double la = shading::srgbToLinear(a / 255.0), lb = shading::srgbToLinear(b / 255.0);
        const double mean = 0.0 + 0.25 * la + 0.25 * lb + 0.25 * la + 0.25 * lb;  // the box's order
        return static_cast<int>(std::clamp(std::lround(shading::linearToSrgb(mean) * 255.0), 0L, 255L));
    };
    int wrong = 0;
    for (int b = 0; b < 256; ++b) {
        for (int a = 0; a < 256; ++a) {
            const uint8_t* texel = &levels[0].rgba[(static_cast<size_t>(b) * 256 + a) * 4];
            wrong += texel[0] != expected(a, b);
            wrong += texel[1] != expected(255 - a, 255 - b);
            wrong += texel[3] != std::lround(0.5 * a + 0.5 * b);
        }
    }
    EXPECT_EQ(wrong, 0);
}

TEST(Mipmaps, EvenLevelsAreTheMeansOfTheirFourTexels) {
    // Random texels, so each 2x2 box holds four different codes: a level of an even-sized texture is the mean
    // of the four in linear light, encoded by the formula (colour), or their mean rounded, halves up (alpha).
    Texture noise;
    noise.width = 64;
    noise.height = 32;
    uint32_t state = 12345u;
    std::vector<uint8_t> rgba;
    for (int i = 0; i < noise.width * noise.height * 4; ++i) {
        state = state * 1664525u + 1013904223u;
        rgba.push_back(static_cast<uint8_t>(state >> 24));
    }
    noise.rgba = texels(std::move(rgba));
    const std::vector<TextureLevel> levels = mipmapChain(noise, true);
    ASSERT_EQ(levels[0].width, 32);
    ASSERT_EQ(levels[0].height, 16);
    int wrong = 0;
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 32; ++x) {
            auto code = [&](int dx, int dy, int c) {
                return (*noise.rgba)[((static_cast<size_t>(2 * y + dy) * 64) + 2 * x + dx) * 4 + c];
            };
            for (int c = 0; c < 4; ++c) {
                int expected;
                if (c < 3) {
                    auto linear = [&](int dx, int dy) {
                        return 0.25 * shading::srgbToLinear(code(dx, dy, c) / 255.0);
                    };
                    const double mean = 0.0 + linear(0, 0) + linear(1, 0) + linear(0, 1) + linear(1, 1);
                    expected = static_cast<int>(
                        std::clamp(std::lround(shading::linearToSrgb(mean) * 255.0), 0L, 255L));
                } else {
                    expected = static_cast<int>(std::floor(
                        (code(0, 0, c) + code(1, 0, c) + code(0, 1, c) + code(1, 1, c)) / 4.0 + 0.5));
                }
                wrong += levels[0].rgba[(static_cast<size_t>(y) * 32 + x) * 4 + c] != expected;
            }
        }
    }
    EXPECT_EQ(wrong, 0);
}

TEST(TextureSampling, WrapModesFollowTheSamplersDefinitions) {
    // Texel i of a row of n, by repeated steps of a period (repeat: n; mirrored repeat: 2n, its second half
    // reflected), or clamped to the edge: for every size up to 7 and indices far on both sides.
    auto stepInto = [](int i, int period) {
        while (i < 0) i += period;
        while (i >= period) i -= period;
        return i;
    };
    // wrapTexels gives texel i and texel i + 1 of a bilinear footprint.
    int wrong = 0;
    for (int n = 1; n <= 7; ++n) {
        for (int i = -40; i <= 40; ++i) {
            for (int k = 0; k < 2; ++k) {
                const int j = i + k;
                const int mirrored = stepInto(j, 2 * n);
                wrong +=
                    shading::wrapTexels(i, n, VKRT_WRAP_REPEAT)[k] != static_cast<uint32_t>(stepInto(j, n));
                wrong += shading::wrapTexels(i, n, VKRT_WRAP_MIRROR)[k] !=
                         static_cast<uint32_t>(mirrored < n ? mirrored : 2 * n - 1 - mirrored);
                wrong += shading::wrapTexels(i, n, VKRT_WRAP_CLAMP)[k] !=
                         static_cast<uint32_t>(std::clamp(j, 0, n - 1));
            }
        }
    }
    EXPECT_EQ(wrong, 0);
}

TEST(TextureSampling, NearestFilteringReadsTheNearestTexelExactly) {
    // A 5 x 3 texture of distinct sRGB texels, read nearest at points all over it and beyond (repeat): each
    // read is the decoded texel whose cell holds the point, to the bit.
    struct Texels {
        std::vector<uint32_t> bits;
        uint32_t texel(uint32_t index) const { return bits[index]; }
    } device;
    for (uint32_t i = 0; i < 15; ++i)
        device.bits.push_back(0x80000000u | (17u * i) | ((250u - 13u * i) << 8));
    shading::GpuTexture texture{};
    texture.width = 5;
    texture.height = 3;
    texture.flags = VKRT_WRAP_REPEAT | (VKRT_WRAP_REPEAT << 2u) | VKRT_TEXTURE_NEAREST;
    const double within[] = {0.02, 0.3, 0.7, 0.98};  // where in its cell, near both edges too
    int wrong = 0;
    for (int cy = -4; cy < 7; ++cy) {
        for (int cx = -6; cx < 11; ++cx) {
            const int column = ((cx % 5) + 5) % 5, row = ((cy % 3) + 3) % 3;
            const glm::dvec4 expected = shading::decodeTexel(device.bits[row * 5 + column], true);
            for (double fy : within) {
                for (double fx : within) {
                    const glm::dvec2 uv((cx + fx) / 5.0, (cy + fy) / 3.0);
                    wrong += shading::sampleTexture(device, texture, uv, true, 0.0) != expected;
                }
            }
        }
    }
    EXPECT_EQ(wrong, 0);
}

TEST(GltfLoader, NodeAnimationsPlacePrimitivesAtTheShutterEnds) {
    // scenes/motion-blur.gltf: shutter [0, 0.5] from the scene's extras; a cube sliding +1.5 units/s in x
    // (LINEAR), a cube turning 90 degrees/s about y (LINEAR), a ball jumping up 0.8 at t = 0.25 (STEP).
    const Scene scene = loadGltf((test::sourceDir() / "scenes/motion-blur.gltf").string());
    EXPECT_EQ(scene.shutterOpen, 0.0);
    EXPECT_EQ(scene.shutterClose, 0.5);
    ASSERT_TRUE(scene.moving());
    // Rotation and a step inside the shutter: the full set of segments.
    const int segments = scene.motionSegments;
    ASSERT_EQ(segments, kMotionSegments);
    ASSERT_EQ(scene.trianglePoses.size(), scene.triangles.size() * segments);
    ASSERT_EQ(scene.spherePoses.size(), static_cast<size_t>(segments));
    size_t sliding = 0, turning = 0, still = 0;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::vec3 a = scene.triangles[i].v0,
                        b = scene.trianglePose(static_cast<uint32_t>(i), segments).v0;
        const glm::vec3 shift = b - a;
        if (glm::length(shift) == 0.0f) {
            ++still;
        } else if (std::abs(shift.x - 0.75f) < 1e-5f && std::abs(shift.y) < 1e-5f &&
                   std::abs(shift.z) < 1e-5f) {
            ++sliding;
        } else {
            // Turning about the cube's vertical axis through (1.6, *, 1.0) (scene coordinates are
            // re-centred): the height and the distance from the axis stay, the angle grows by 45 degrees.
            const glm::dvec3 axis = glm::dvec3(1.6, 0.0, 1.0) - scene.origin;
            const glm::dvec2 p(a.x - axis.x, a.z - axis.z), q(b.x - axis.x, b.z - axis.z);
            EXPECT_NEAR(a.y, b.y, 1e-5);
            EXPECT_NEAR(glm::length(p), glm::length(q), 1e-5);
            const double turned = std::atan2(p.x * q.y - p.y * q.x, glm::dot(p, q));
            EXPECT_NEAR(std::abs(turned), M_PI / 4.0, 1e-5);
            ++turning;
        }
    }
    EXPECT_EQ(sliding, 12u);
    EXPECT_EQ(turning, 12u);
    EXPECT_EQ(still, scene.triangles.size() - 24u);
    // STEP: the ball stays until t = 0.25 (pose 8 of 16 over [0, 0.5]), then is 0.8 higher.
    const uint32_t ball = static_cast<uint32_t>(scene.triangles.size());
    EXPECT_EQ(scene.spherePose(ball, 7).center.y, scene.spheres[0].center.y);
    EXPECT_NEAR(scene.spherePose(ball, 8).center.y - scene.spheres[0].center.y, 0.8f, 1e-5f);
    EXPECT_NEAR(scene.spherePose(ball, segments).center.y - scene.spheres[0].center.y, 0.8f, 1e-5f);
    // Shutter closed: nothing moves.
    LoadOptions closed;
    closed.shutter = std::array<double, 2>{0.25, 0.25};
    const Scene frozen = loadGltf((test::sourceDir() / "scenes/motion-blur.gltf").string(), closed);
    EXPECT_FALSE(frozen.moving());
    EXPECT_NEAR(frozen.spheres[0].center.y + frozen.origin.y, 1.3, 1e-5);  // STEP: the second key from 0.25
}

TEST(GltfLoader, BoxCounts) {
    REQUIRE_SCENES_REAL();
    for (const char* file : {"khronos-Box/glTF/Box.gltf", "khronos-Box/glTF-Binary/Box.glb"}) {
        const Scene scene = loadReal(file);
        EXPECT_EQ(scene.triangles.size(), 12u) << file;
        EXPECT_TRUE(scene.cameras.empty()) << file;
        // The Box's node rotates it by -90 degrees about x: its 1 x 1 x 1 extent stays a unit cube.
        EXPECT_NEAR(scene.bounds.extent().x, 1.0f, 1e-5f);
        EXPECT_NEAR(scene.bounds.extent().y, 1.0f, 1e-5f);
        EXPECT_NEAR(scene.bounds.extent().z, 1.0f, 1e-5f);
    }
}

TEST(GltfLoader, DuckHasTexturedMaterialAndCamera) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-Duck/glTF/Duck.gltf");
    EXPECT_EQ(scene.triangles.size(), 4212u);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_EQ(scene.cameras[0].projection, Projection::Perspective);
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_GT(scene.textures[0].width, 0);
    EXPECT_EQ(scene.materials[scene.triangles[0].material].baseColorTexture.texture, 0);
    // The binary and text versions are the same model.
    EXPECT_EQ(loadReal("khronos-Duck/glTF-Binary/Duck.glb").triangles.size(), 4212u);
}

TEST(GltfLoader, CamerasPerspectiveAndOrthographic) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-Cameras/glTF/Cameras.gltf");
    ASSERT_EQ(scene.cameras.size(), 2u);
    EXPECT_EQ(scene.cameras[0].projection, Projection::Perspective);
    EXPECT_EQ(scene.cameras[1].projection, Projection::Orthographic);
    EXPECT_EQ(selectCamera(scene, 1, 1.0).projection, Projection::Orthographic);
    EXPECT_THROW(selectCamera(scene, 2, 1.0), SceneError);
}

// A camera mirrored with what it sees sees it as before: its +X is to the right and its +Y up
// (glTF 2.0 3.10.1), whatever the sign of its node's determinant. (Right as forward x up turned the image of
// a mirrored scene.)
TEST(GltfLoader, MirroredCameraKeepsItsAxes) {
    const auto folder = test::temporaryFolder();
    for (const char* scale : {"[1, 1, 1]", "[-1, 1, 1]", "[1, -1, 1]", "[-2, -2, -2]"}) {
        const std::filesystem::path file = folder / "mirrored.gltf";
        test::writeText(file, std::string(R"({
            "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0,
            "scenes": [{"nodes": [0]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
            "nodes": [
                {"scale": )") + scale +
                                  R"(, "rotation": [0, 0.3826834, 0, 0.9238795], "children": [1, 2]},
                {"translation": [0.5, 0.2, -3], "extensions": {"VKRT_sphere": {"radius": 0.1}}},
                {"camera": 0}
            ]})");
        const Scene scene = loadGltf(file.string());
        ASSERT_EQ(scene.cameras.size(), 1u);
        const Camera& camera = scene.cameras[0];
        // The sphere lies right of the view's centre and above it, in front, wherever the parent puts both.
        const glm::dvec3 toSphere = glm::dvec3(scene.spheres[0].center) - camera.position;
        EXPECT_GT(glm::dot(toSphere, camera.forward), 0.0) << scale;
        EXPECT_GT(glm::dot(toSphere, camera.right), 0.0) << scale;
        EXPECT_GT(glm::dot(toSphere, camera.up), 0.0) << scale;
        EXPECT_NEAR(glm::dot(camera.right, camera.forward), 0.0, 1e-12) << scale;
        EXPECT_NEAR(glm::dot(camera.up, camera.forward), 0.0, 1e-12) << scale;
        EXPECT_NEAR(glm::dot(camera.up, camera.right), 0.0, 1e-12) << scale;
        EXPECT_NEAR(glm::length(camera.up), 1.0, 1e-12) << scale;
    }
}

// A camera under a node scaled to nothing (a collapsed rig: valid glTF) is refused only when it is chosen.
// Nodes 1 and 3 share camera 0 and only node 3 is singular: the refusal names the node, which the cameras[]
// index alone ("camera 0") did not tell apart from the usable one.
TEST(GltfLoader, CameraWithASingularTransformIsRefusedOnlyWhenChosenNamingItsNode) {
    const std::filesystem::path file = test::temporaryFolder() / "collapsed.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
        "nodes": [
            {"extensions": {"VKRT_sphere": {"radius": 0.5}}},
            {"translation": [0, 0, 3], "camera": 0},
            {"scale": [0, 0, 0], "children": [3]},
            {"camera": 0}
        ]})");
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.cameras.size(), 2u);
    EXPECT_NEAR(selectCamera(scene, 0, 1.0).forward.z, -1.0, 1e-12);
    try {
        selectCamera(scene, 1, 1.0);
        ADD_FAILURE() << "the collapsed camera was chosen";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("camera 0 at node 3: its node transform is singular"),
                  std::string::npos)
            << e.what();
    }
}

// A camera under nested scales whose product is 1e-190 (five of 1e-38, each within single precision) is
// valid and not singular: it has the axes it has unscaled. Normalising its axes, whose squared lengths
// (1e-380) underflow double precision, refused it as singular.
TEST(GltfLoader, CameraUnderATinyButValidScaleKeepsItsAxes) {
    const auto folder = test::temporaryFolder();
    auto load = [&](const char* scale) {
        const std::filesystem::path file = folder / "tiny.gltf";
        std::string nodes;
        for (int level = 1; level <= 5; ++level) {
            nodes += std::string(R"({"scale": )") + scale + R"(, "children": [)" + std::to_string(level + 1) +
                     "]},";
        }
        test::writeText(file, std::string(R"({
            "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0,
            "scenes": [{"nodes": [0, 1]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
            "nodes": [
                {"extensions": {"VKRT_sphere": {"radius": 0.5}}},
                )") + nodes + R"(
                {"translation": [0, 0, 3], "rotation": [0.1, 0.38, 0.2, 0.8975522], "camera": 0}
            ]})");
        return selectCamera(loadGltf(file.string()), 0, 1.0);
    };
    const Camera unscaled = load("[1, 1, 1]");
    const Camera tiny = load("[1e-38, 1e-38, 1e-38]");
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(tiny.forward[k], unscaled.forward[k], 1e-12) << k;
        EXPECT_NEAR(tiny.right[k], unscaled.right[k], 1e-12) << k;
        EXPECT_NEAR(tiny.up[k], unscaled.up[k], 1e-12) << k;
    }
}

// A primitive without POSITION is valid glTF and is not rendered (2.0 3.7.2.1): the rest of the file is.
TEST(GltfLoader, PrimitiveWithoutPositionsIsLeftOutWithAWarning) {
    const std::filesystem::path file = test::temporaryFolder() / "no-positions.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"NORMAL": 0}}]}],
        "nodes": [{"mesh": 0}, {"extensions": {"VKRT_sphere": {"radius": 0.5}}}]
    })");
    const Scene scene = loadGltf(file.string());
    EXPECT_EQ(scene.primitiveCount(), 1u);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("mesh 0 primitive 0 has no POSITION attribute; it is left out"),
              std::string::npos)
        << scene.warnings[0];
}

// What the core schema leaves open stays open: an animation channel may target a path an extension defines
// (passed over: it moves no node here), and `extras` are every application's, so vkrt's own keys there
// holding something else (another tool's data) are passed over with a warning. (KHR_animation_pointer's
// channels, which name no node, are refused by the tinygltf that Debian 12 packages.)
TEST(GltfLoader, ExtensionPathsAndOtherToolsExtrasAreAccepted) {
    const std::filesystem::path file = test::temporaryFolder() / "open.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0,
        "scenes": [{"nodes": [0, 1], "extras": {"shutter": "1/60"}}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1},
                     "extras": {"aperture": "f/2.8", "focusDistance": 2.5}}],
        "accessors": [{"componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
                      {"componentType": 5126, "count": 2, "type": "SCALAR"}],
        "animations": [{"samplers": [{"input": 0, "output": 1}],
                        "channels": [{"sampler": 0, "target": {"node": 1, "path": "EXT_some_property"}}]}],
        "nodes": [{"extensions": {"VKRT_sphere": {"radius": 0.5}}}, {"translation": [0, 0, 3], "camera": 0}]
    })");
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_EQ(scene.cameras[0].aperture, 0.0);
    EXPECT_EQ(scene.cameras[0].focusDistance, 2.5);
    EXPECT_EQ(scene.shutterOpen, 0.0);
    EXPECT_EQ(scene.shutterClose, 0.0);
    ASSERT_EQ(scene.warnings.size(), 2u);
    EXPECT_NE(scene.warnings[0].find("extras.shutter is not [open, close]; it is ignored"), std::string::npos)
        << scene.warnings[0];
    EXPECT_NE(scene.warnings[1].find("extras.aperture is not a number; it is ignored"), std::string::npos)
        << scene.warnings[1];
    // A number there is vkrt's, and checked as the file's own are: one beyond single precision is refused.
    std::string text;
    {
        std::ifstream in(file);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const size_t at = text.find("\"f/2.8\"");
    ASSERT_NE(at, std::string::npos);
    test::writeText(file, text.replace(at, 7, "1e39"));
    try {
        loadGltf(file.string());
        ADD_FAILURE() << "an aperture of 1e39 was accepted";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("'aperture' is beyond single precision's range"),
                  std::string::npos)
            << e.what();
    }
}

// Positions are stored relative to where the scene's detail is: a ground sphere of radius 1e5 under small
// objects does not pull the origin towards its centre (the middle of all bounds lay 5e4 below them, where the
// GPU's float positions kept a hundredth of a unit and contact shadows differed from the CPU's).
// Finite corners near float's range load: they were checked by their float sum, which overflowed
// (2.5e38 + 2.3e38 is infinite) and refused the triangle as moved out of range.
TEST(GltfLoader, CornersNearFloatsRangeLoad) {
    test::GltfDocument d;
    const int positions = d.floats(
        {1.28e38f, -2.59e38f, -1.91e38f, -1.97e38f, 2.54e38f, -1.53e38f, 2.30e38f, 0.95e38f, -1.71e38f},
        "VEC3");
    d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}};
    d.node({{"mesh", 0}});
    const auto file = test::temporaryFolder() / "wide.gltf";
    d.write(file);
    EXPECT_EQ(loadGltf(file.string()).triangles.size(), 1u);
}

// One triangle 1e17 away in the same primitive as a thousand small ones: the primitive's bounds reach 1e17,
// and a middle taken from them (5e16) left the small triangles, stored in float about it, degenerate on
// both devices. The middle is the median of the primitive's vertices.
TEST(GltfLoader, AFarTriangleDoesNotPullTheOriginAway) {
    const glm::dvec3 near(3.0, 2.0, 1.0);
    std::vector<float> positions;
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 corner = near + glm::dvec3(0.01 * (i % 10), 0.01 * (i / 10 % 10), 0.01 * (i / 100));
        for (const glm::dvec3& offset :
             {glm::dvec3(0.0), glm::dvec3(0.005, 0.0, 0.0), glm::dvec3(0.0, 0.005, 0.0)})
            for (int axis = 0; axis < 3; ++axis)
                positions.push_back(static_cast<float>((corner + offset)[axis]));
    }
    for (const float far : {1e17f, 1.0001e17f, 1e17f}) positions.insert(positions.end(), {far, far, 1e17f});
    positions[positions.size() - 2] = 1.0001e17f;
    test::GltfDocument d;
    const int accessor = d.floats(positions, "VEC3");
    glm::vec3 low(positions[0], positions[1], positions[2]), high = low;
    for (size_t i = 0; i < positions.size(); i += 3) {
        low = glm::min(low, glm::vec3(positions[i], positions[i + 1], positions[i + 2]));
        high = glm::max(high, glm::vec3(positions[i], positions[i + 1], positions[i + 2]));
    }
    d.json["accessors"][accessor]["min"] = {low.x, low.y, low.z};
    d.json["accessors"][accessor]["max"] = {high.x, high.y, high.z};
    d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", accessor}}}}}}}};
    d.node({{"mesh", 0}});
    const auto file = test::temporaryFolder() / "far.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    EXPECT_LT(glm::length(scene.origin - near), 1.0) << scene.origin.x << " " << scene.origin.y;
    ASSERT_EQ(scene.triangles.size(), 1001u);
    size_t kept = 0;  // small triangles whose corners are where the file puts them, to float's precision
    for (const Triangle& t : scene.triangles) {
        const glm::dvec3 v0 = glm::dvec3(t.v0) + scene.origin, v1 = glm::dvec3(t.v1) + scene.origin;
        if (glm::length(v0 - near) < 1.0 && std::abs(glm::length(v1 - v0) - 0.005) < 1e-6) ++kept;
    }
    EXPECT_EQ(kept, 1000u);

    // Of a primitive of 9000 vertices every third is read (at most 4096 are), sparse substitutions included:
    // here exactly those read are moved to (5, 5, 5), the others stay at zero.
    test::GltfDocument sparse;
    std::vector<uint16_t> indices;
    std::vector<float> values;
    for (uint16_t i = 0; i < 9000; i += 3) {
        indices.push_back(i);
        values.insert(values.end(), {5.0f, 5.0f, 5.0f});
    }
    const int indexView = sparse.json["bufferViews"].size();
    sparse.unsignedShorts(indices, "SCALAR");
    const int valueView = sparse.json["bufferViews"].size();
    sparse.floats(values, "VEC3");
    sparse.json["accessors"].push_back({{"componentType", 5126},
                                        {"count", 9000},
                                        {"type", "VEC3"},
                                        {"min", {0, 0, 0}},
                                        {"max", {5, 5, 5}},
                                        {"sparse",
                                         {{"count", indices.size()},
                                          {"indices", {{"bufferView", indexView}, {"componentType", 5123}}},
                                          {"values", {{"bufferView", valueView}}}}}});
    sparse.json["meshes"] = {
        {{"primitives", {{{"attributes", {{"POSITION", sparse.json["accessors"].size() - 1}}}}}}}};
    sparse.node({{"mesh", 0}});
    sparse.write(file);
    EXPECT_LT(glm::length(loadGltf(file.string()).origin - glm::dvec3(5.0)), 1e-9);
}

// A triangle under node 0, moved along x by the translation animations `clips` (name, STEP keys and their x).
struct Clip {
    std::string name;
    std::vector<float> times, x;
};
std::filesystem::path animatedTriangleFile(const std::vector<Clip>& clips) {
    test::GltfDocument d;
    const int positions = d.floats({0, 0, 0, 0.1f, 0, 0, 0, 0.1f, 0}, "VEC3");
    d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}};
    d.node({{"mesh", 0}});
    for (const Clip& clip : clips) {
        std::vector<float> values;
        for (float x : clip.x) values.insert(values.end(), {x, 0.0f, 0.0f});
        const int input = d.floats(clip.times, "SCALAR"), output = d.floats(values, "VEC3");
        d.json["animations"].push_back(
            {{"name", clip.name},
             {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
             {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "STEP"}}}}});
    }
    const auto file = test::temporaryFolder() / "animated.gltf";
    d.write(file);
    return file;
}

double triangleX(const Scene& scene) {
    return scene.triangles[0].v0.x + scene.origin.x;
}

// At a key's time a STEP animation takes that key's value: key times are floats, and the time 0.1 lies just
// below the key 0.1f; compared in double, it took the key before (every frame of a 30 fps animation rendered
// at its key showed the frame before).
TEST(GltfLoader, AnAnimationAtAKeysTimeTakesThatKey) {
    const auto file = animatedTriangleFile({{"steps", {0.0f, 0.1f, 0.2f}, {-1.0f, 1.0f, 2.0f}}});
    for (const auto& [time, x] : {std::pair{0.0, -1.0}, {0.05, -1.0}, {0.1, 1.0}, {0.15, 1.0}, {0.2, 2.0}}) {
        LoadOptions options;
        options.shutter = std::array<double, 2>{time, time};
        EXPECT_NEAR(triangleX(loadGltf(file.string(), options)), x, 1e-6) << "at " << time;
    }
    const auto frames =
        animatedTriangleFile({{"frames", {0.0f, 1.0f / 30, 2.0f / 30, 3.0f / 30}, {0, 1, 2, 3}}});
    for (int frame = 0; frame < 4; ++frame) {
        LoadOptions options;
        options.shutter = std::array<double, 2>{frame / 30.0, frame / 30.0};
        EXPECT_NEAR(triangleX(loadGltf(frames.string(), options)), frame, 1e-6) << "frame " << frame;
    }
}

// A file's animations are clips (an idle, a walk, a run on the same joints): the first plays, vkrt says so
// where there are several, and --animation picks another by index or name. All of them once played together,
// the last channel of a node winning.
TEST(GltfLoader, OneAnimationPlaysAndItCanBeChosen) {
    const auto file =
        animatedTriangleFile({{"idle", {0.0f, 1.0f}, {-2.0f, -2.0f}}, {"run", {0.0f, 1.0f}, {2.0f, 2.0f}}});
    const Scene first = loadGltf(file.string());
    EXPECT_NEAR(triangleX(first), -2.0, 1e-6);
    bool said = false;
    for (const std::string& warning : first.warnings)
        said |= warning.find("the file has 2 animations; animation 0 (\"idle\") plays") != std::string::npos;
    EXPECT_TRUE(said);
    for (const char* run : {"1", "run"}) {
        LoadOptions options;
        options.animation = run;
        const Scene chosen = loadGltf(file.string(), options);
        EXPECT_NEAR(triangleX(chosen), 2.0, 1e-6) << run;
        for (const std::string& warning : chosen.warnings)
            EXPECT_EQ(warning.find("animations;"), std::string::npos);
    }
    for (const char* missing : {"2", "walk", "-1"}) {
        LoadOptions options;
        options.animation = missing;
        try {
            loadGltf(file.string(), options);
            ADD_FAILURE() << missing;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("no such animation (the file has animation 0 (\"idle\"), "
                                                 "animation 1 (\"run\"))"),
                      std::string::npos)
                << e.what();
        }
    }
}

TEST(GltfLoader, HugeGroundDoesNotPullTheOriginAway) {
    const std::filesystem::path file = test::temporaryFolder() / "ground.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"translation": [0, -100000, 0], "extensions": {"VKRT_sphere": {"radius": 100000}}},
            {"translation": [0, 0.5, 0], "extensions": {"VKRT_sphere": {"radius": 0.5}}},
            {"translation": [1.5, 0.3, 0.2], "extensions": {"VKRT_sphere": {"radius": 0.3}}}
        ]})");
    const Scene scene = loadGltf(file.string());
    EXPECT_LT(glm::length(scene.origin - glm::dvec3(0.0, 0.5, 0.0)), 2.0) << scene.origin.y;
    // Placed where the file says, whatever the origin.
    EXPECT_NEAR(scene.spheres[2].center.x + scene.origin.x, 1.5, 1e-6);
    EXPECT_NEAR(scene.spheres[0].center.y + scene.origin.y, -100000.0, 1e-2);

    // One object on the ground: the median of two centres would be the ground's, 1e6 below the object (where
    // the GPU's ray offsets were 4 units and its contact shadows vanished); the ground stands for its top.
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"translation": [0, -1000000, 0], "extensions": {"VKRT_sphere": {"radius": 1000000}}},
            {"translation": [2, 0.3, -1], "extensions": {"VKRT_sphere": {"radius": 0.3}}}
        ]})");
    const Scene one = loadGltf(file.string());
    EXPECT_LT(glm::length(one.origin - glm::dvec3(2.0, 0.3, -1.0)), 1.0)
        << one.origin.x << " " << one.origin.y << " " << one.origin.z;
}

// Texture coordinates: a non-finite one is refused, as positions, colours and tangents are; a texture reading
// TEXCOORD_1 on a mesh without it reads TEXCOORD_0 (its values, not zeros), and vkrt says so; one reading a
// set the mesh lacks altogether is named too.
TEST(GltfLoader, TextureCoordinatesAreFiniteAndTheSetATextureReadsIsThere) {
    const auto folder = test::temporaryFolder();
    auto write = [&](float u, int texCoord, const char* attributes = R"("POSITION": 0, "TEXCOORD_0": 1)") {
        const std::vector<float> data = {0, 0, 0, 1, 0, 0, 0, 1, 0, u, 0, 1, 0, 0, 1};
        test::writeText(folder / "triangle.bin", std::string(reinterpret_cast<const char*>(data.data()), 60));
        const std::filesystem::path file = folder / "triangle.gltf";
        test::writeText(file, R"({
            "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "buffers": [{"uri": "triangle.bin", "byteLength": 60}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]},
                          {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}],
            "images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="}],
            "textures": [{"source": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": )" +
                                  std::to_string(texCoord) + R"(}}}],
            "meshes": [{"primitives": [{"attributes": {)" +
                                  attributes + R"(}, "material": 0}]}],
            "nodes": [{"mesh": 0}]
        })");
        return file.string();
    };
    EXPECT_TRUE(loadGltf(write(0.5f, 0)).warnings.empty());
    const Scene second = loadGltf(write(0.5f, 1));
    ASSERT_EQ(second.warnings.size(), 1u);
    EXPECT_NE(second.warnings[0].find(
                  "has no TEXCOORD_1, which its material's textures read; they read TEXCOORD_0"),
              std::string::npos)
        << second.warnings[0];
    ASSERT_EQ(second.uv1.size(), 1u);
    for (int corner = 0; corner < 3; ++corner) EXPECT_EQ(second.uv1[0][corner], second.shading[0].uv[corner]);
    for (int texCoord : {0, 1}) {
        const Scene none = loadGltf(write(0.5f, texCoord, R"("POSITION": 0)"));
        ASSERT_EQ(none.warnings.size(), 1u);
        EXPECT_NE(none.warnings[0].find("has no TEXCOORD_" + std::to_string(texCoord) +
                                        ", which its material's textures read; they read (0, 0)"),
                  std::string::npos)
            << none.warnings[0];
    }
    try {
        loadGltf(write(std::nanf(""), 0));
        ADD_FAILURE() << "a NaN texture coordinate was accepted";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("TEXCOORD_0 has a non-finite value at vertex 0"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfLoader, PunctualLightsInPhotometricUnits) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("playcanvas-lights/Lights.glb");
    int point = 0, spot = 0, directional = 0;
    for (const PunctualLight& light : scene.lights) {
        point += light.type == LightType::Point;
        spot += light.type == LightType::Spot;
        directional += light.type == LightType::Directional;
        EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-9);
        if (light.type == LightType::Spot) {
            EXPECT_LT(light.innerConeAngle, light.outerConeAngle);
        }
    }
    EXPECT_EQ(point, 1);
    EXPECT_EQ(spot, 2);
    EXPECT_EQ(directional, 1);
}

TEST(GltfLoader, GpuInstancingExpandsInstances) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-SimpleInstancing/SimpleInstancing.glb");
    EXPECT_EQ(scene.triangles.size(), 12u * 125u);
}

// Two meshes, each used by several nodes, interleaved (A, B, A, B, A, then B under the last A), so that
// the loader's decode-once cache is hit for every later instance. With `sharedMeshes` false, every node
// gets its own copy of its mesh: nothing is shared, so each instance is decoded on its own.
// Mesh A: one triangle with normals (material 0). Mesh B: a 2 x 2 quad of two indexed triangles, no
// normals (material 1). Every transform is exact in binary, so hand-placed positions compare with ==.
std::filesystem::path writeInstancedMeshes(const std::filesystem::path& folder, bool sharedMeshes) {
    const float triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float quad[12] = {0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0};
    const uint16_t quadIndices[6] = {0, 1, 2, 0, 2, 3};
    std::string bytes(132, '\0');
    std::memcpy(bytes.data(), triangle, 36);
    std::memcpy(bytes.data() + 36, normals, 36);
    std::memcpy(bytes.data() + 72, quad, 48);
    std::memcpy(bytes.data() + 120, quadIndices, 12);
    const std::string name = sharedMeshes ? "shared" : "copies";
    test::writeText(folder / (name + ".bin"), bytes);

    using nlohmann::json;
    const json meshA = {
        {"name", "A"}, {"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"material", 0}}}}};
    const json meshB = {
        {"name", "B"},
        {"primitives", {{{"attributes", {{"POSITION", 2}}}, {"indices", 3}, {"material", 1}}}}};
    json nodes = {
        {{"translation", {4, 0, 0}}},
        // 90 degrees about z, then up by 8 (column-major).
        {{"matrix", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 8, 0, 1}}},
        {{"translation", {0, 0, -4}}, {"scale", {2, 2, 2}}},
        // Mirrored: the loader swaps two corners to keep the winding.
        {{"translation", {-8, 0, 0}}, {"scale", {-1, 1, 1}}},
        // 180 degrees about x, with a child that inherits it.
        {{"rotation", {1, 0, 0, 0}}, {"children", {5}}},
        {{"translation", {1, 1, 1}}},
    };
    const int nodeMesh[6] = {0, 1, 0, 1, 0, 1};  // A, B, A, B, A, B
    json meshes = sharedMeshes ? json{meshA, meshB} : json::array();
    for (int i = 0; i < 6; ++i) {
        if (sharedMeshes) {
            nodes[i]["mesh"] = nodeMesh[i];
        } else {
            meshes.push_back(nodeMesh[i] == 0 ? meshA : meshB);
            nodes[i]["mesh"] = i;
        }
    }
    const json document = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1, 2, 3, 4}}}}},
        {"nodes", nodes},
        {"meshes", meshes},
        {"materials", {{{"name", "a"}}, {{"name", "b"}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", 3},
           {"type", "VEC3"},
           {"min", {0, 0, 0}},
           {"max", {1, 1, 0}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
          {{"bufferView", 2},
           {"componentType", 5126},
           {"count", 4},
           {"type", "VEC3"},
           {"min", {0, 0, 0}},
           {"max", {2, 2, 0}}},
          {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
          {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 36}},
          {{"buffer", 0}, {"byteOffset", 72}, {"byteLength", 48}},
          {{"buffer", 0}, {"byteOffset", 120}, {"byteLength", 12}}}},
        {"buffers", {{{"uri", name + ".bin"}, {"byteLength", 132}}}},
    };
    const std::filesystem::path file = folder / (name + ".gltf");
    test::writeText(file, document.dump());
    return file;
}

// An image's decoded size is read from its header and counted against the memory before it is decoded: a PNG
// of 118 bytes that claims 20000 x 20000 pixels is refused in one line naming the figures (three valid 16384
// x 16384 PNGs in a 3 MB file took 6.3 GB before --max-memory 1GiB refused them).
TEST(GltfLoader, ImagesAreCountedAgainstTheMemoryBeforeTheyAreDecoded) {
    const std::filesystem::path file = texturedSphere(
        "claims",
        "iVBORw0KGgoAAAANSUhEUgAATiAAAE4gCAAAAADGGxnlAAAADElEQVR4nGNgoAwAAABAAAG3NHzvAAAAAElFTkSuQmCC");
    LoadOptions options;
    options.maxSceneBytes = 64u << 20;
    options.memorySource = "--max-memory";
    try {
        loadGltf(file.string(), options);
        ADD_FAILURE() << "an image of 20000 x 20000 pixels loaded in 64 MiB";
    } catch (const SceneError& e) {
        const std::string message = e.what();
        EXPECT_NE(
            message.find("its 20000 x 20000 pixels would take 2.98 GiB of host memory beside 0 B of other "
                         "images, and 64.0 MiB is available (--max-memory)"),
            std::string::npos)
            << message;
    }
}

// The triangles a file places are counted against the host memory before they are placed: a file of a few
// bytes whose instances make a billion triangles is refused in one line (MemoryError, exit 2), not after
// taking all the memory there is. The interleaved meshes place 9 triangles: allowed the memory of 9 they
// load, of 8 not.
TEST(GltfLoader, PlacedTrianglesAreCountedAgainstTheMemoryBeforeTheyArePlaced) {
    const std::filesystem::path file = writeInstancedMeshes(test::temporaryFolder(), true);
    LoadOptions options;
    options.maxSceneBytes = 9 * (sizeof(Triangle) + sizeof(TriangleShading));
    EXPECT_EQ(loadGltf(file.string(), options).triangles.size(), 9u);
    options.maxSceneBytes -= 1;
    options.memorySource = "--max-memory";
    try {
        loadGltf(file.string(), options);
        ADD_FAILURE() << "loaded 9 triangles in the memory of fewer";
    } catch (const MemoryError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(file.string()), std::string::npos) << message;
        EXPECT_NE(message.find("up to 9 triangles"), std::string::npos) << message;
        EXPECT_NE(message.find("(--max-memory)"), std::string::npos) << message;
    }
    // Under motion blur each pose keeps the corners, not the shading: the motion-blur scene loads in exactly
    // what its triangles and the 26 floats of its animation's keys take (it was refused in 2.3 times that).
    const std::string moving = (test::sourceDir() / "scenes/motion-blur.gltf").string();
    const Scene scene = loadGltf(moving);
    ASSERT_GT(scene.motionSegments, 1);
    const uint64_t poses = static_cast<uint64_t>(scene.motionSegments) + 1;
    LoadOptions exact;
    exact.maxSceneBytes =
        scene.triangles.size() * (sizeof(Triangle) * poses + sizeof(TriangleShading)) + 26 * sizeof(float);
    EXPECT_EQ(loadGltf(moving, exact).triangles.size(), scene.triangles.size());
    exact.maxSceneBytes -= 1;
    EXPECT_THROW(loadGltf(moving, exact), MemoryError);
}

// Every vertex attribute is counted against the memory before it is read, beside what is read already, the
// vertices no triangle uses too: a triangle whose POSITION and NORMAL claim a million vertices (sparse
// accessors of a few bytes) takes 36 MB to read its positions (a double and a float per value) and 36 MB more
// for its normals beside the 12 MB of positions kept. Refused in 16 MiB, its positions alone are read in 40
// MiB, and its normals refused there (at 2^26 vertices they took 2.4 GB under --max-memory 500M).
TEST(GltfLoader, VertexAttributesAreCountedAgainstTheMemoryBeforeTheyAreRead) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d;
    const size_t vertices = 1000000;
    const int positions = d.sparsePositions(vertices, {0, 1, 2}, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int normals =
        d.sparseOnly(vertices, {0, 1, 2}, std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, 5126, "VEC3");
    const int indices = d.unsignedShorts({0, 1, 2}, "SCALAR");
    d.json["meshes"] = {
        {{"primitives", {{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}}}}};
    d.node({{"mesh", 0}});
    d.write(folder / "positions.gltf");
    d.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = normals;
    d.write(folder / "normals.gltf");
    const auto refusal = [](const std::filesystem::path& file, uint64_t bytes) -> std::string {
        LoadOptions options;
        options.maxSceneBytes = bytes;
        try {
            loadGltf(file.string(), options);
        } catch (const MemoryError& e) {
            return e.what();
        }
        return "loaded";
    };
    EXPECT_NE(refusal(folder / "positions.gltf", 16u << 20).find("mesh 0 primitive 0 POSITION would take"),
              std::string::npos);
    EXPECT_EQ(refusal(folder / "positions.gltf", 40u << 20), "loaded");
    EXPECT_NE(refusal(folder / "normals.gltf", 40u << 20).find("mesh 0 primitive 0 NORMAL would take"),
              std::string::npos);
}

// What a file asks the loader to read for it, refused or loaded under `bytes` of host memory: the
// MemoryError's message, or "loaded".
std::string refusalUnder(const std::filesystem::path& file, uint64_t bytes) {
    LoadOptions options;
    options.maxSceneBytes = bytes;
    options.memorySource = "--max-memory";
    try {
        loadGltf(file.string(), options);
    } catch (const MemoryError& e) {
        return e.what();
    }
    return "loaded";
}

// EXT_mesh_gpu_instancing's attributes are counted against the memory before they are read, and so are the
// transforms made of them, which are held while the instances' triangles are placed. A TRANSLATION of a
// million instances (a sparse accessor of a few bytes) takes 36 MB to read (a double and a float per value):
// refused in 16 MiB before it is read (at 2^26 instances it asked for 9.4 GB, whatever --max-memory said).
// Ten thousand instances of a triangle hold 1.28 MB of transforms beside their 1 MB of triangles: refused in
// 2 MiB, loaded in 4.
TEST(GltfLoader, InstanceAttributesAreCountedAgainstTheMemoryBeforeTheyAreRead) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d;
    const int positions = d.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}};
    const size_t claimedInstances = 1000000, placedInstances = 10000;
    const int claimed = d.sparseOnly(claimedInstances, {0}, std::vector<float>{1, 0, 0}, 5126, "VEC3");
    std::vector<float> offsets;
    for (size_t i = 0; i < placedInstances; ++i) offsets.insert(offsets.end(), {2.0f * i, 0.0f, 0.0f});
    const int placed = d.floats(offsets, "VEC3");
    d.json["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    const int node =
        d.node({{"mesh", 0},
                {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", claimed}}}}}}}});
    d.write(folder / "claimed.gltf");
    d.json["nodes"][node]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = placed;
    d.write(folder / "placed.gltf");
    const std::string refused = refusalUnder(folder / "claimed.gltf", 16u << 20);
    EXPECT_NE(refused.find("node 0 EXT_mesh_gpu_instancing TRANSLATION would take 34.3 MiB"),
              std::string::npos)
        << refused;
    EXPECT_NE(refused.find("(--max-memory)"), std::string::npos) << refused;
    const std::string crowded = refusalUnder(folder / "placed.gltf", 2u << 20);
    EXPECT_NE(crowded.find("node 0 places mesh 0 10000 time(s)"), std::string::npos) << crowded;
    EXPECT_EQ(refusalUnder(folder / "placed.gltf", 4u << 20), "loaded");
}

// An animation's keys are counted against the memory before they are read, and held for the rest of the
// load. A sampler whose input and output claim a million keys (sparse accessors of a few bytes) takes 12 MB
// to read its times (a double and a float each) and 36 MB more for its translations beside the 4 MB of times
// kept: refused in 16 MiB naming the output, before it is read (at 2^26 keys they asked for 2.7 GB, whatever
// --max-memory said). A hundred thousand keys keep 0.4 MB of times and take 3.6 MB to read their translations
// beside them: refused in 3 MiB, loaded in 8.
TEST(GltfLoader, AnimationKeysAreCountedAgainstTheMemoryBeforeTheyAreRead) {
    const auto folder = test::temporaryFolder();
    test::GltfDocument d;
    const int positions = d.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}};
    const int node = d.node({{"mesh", 0}});
    const size_t claimedKeys = 1000000, givenKeys = 100000;
    const int claimedTimes = d.sparseOnly(claimedKeys, {0}, std::vector<float>{0}, 5126, "SCALAR");
    const int claimedTranslations = d.sparseOnly(claimedKeys, {0}, std::vector<float>{0, 0, 0}, 5126, "VEC3");
    std::vector<float> times(givenKeys);
    for (size_t k = 0; k < givenKeys; ++k) times[k] = 0.001f * static_cast<float>(k);
    const int givenTimes = d.floats(times, "SCALAR");
    const int givenTranslations = d.floats(std::vector<float>(3 * givenKeys, 0.0f), "VEC3");
    d.json["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}}}},
         {"samplers", {{{"input", claimedTimes}, {"output", claimedTranslations}}}}}};
    d.write(folder / "claimed.gltf");
    d.json["animations"][0]["samplers"][0] = {{"input", givenTimes}, {"output", givenTranslations}};
    d.write(folder / "given.gltf");
    const std::string refused = refusalUnder(folder / "claimed.gltf", 16u << 20);
    EXPECT_NE(refused.find("animation 0 channel 0 output would take 34.3 MiB"), std::string::npos) << refused;
    EXPECT_NE(refused.find("(--max-memory)"), std::string::npos) << refused;
    const std::string crowded = refusalUnder(folder / "given.gltf", 3u << 20);
    EXPECT_NE(crowded.find("animation 0 channel 0 output would take 3.43 MiB"), std::string::npos) << crowded;
    EXPECT_EQ(refusalUnder(folder / "given.gltf", 8u << 20), "loaded");
}

// A grid of 5,000 triangles with a normal texture, COLOR_0 and TEXCOORD_1: each triangle keeps a tangent
// frame, vertex colours and second texture coordinates beside its corners and shading (Scene's parallel
// arrays), and the load counts them before placing it. Counted without them (100 of the 220 bytes a triangle
// keeps), the file loaded under --max-memory of less than half what it took. Morphed, the mesh also keeps its
// texture coordinates for deriving its tangents again (2 floats a vertex beside the target's 3), counted
// likewise.
TEST(GltfLoader, EveryArrayATriangleKeepsIsCountedAgainstTheMemory) {
    const auto folder = test::temporaryFolder();
    constexpr int kSide = 50;  // squares a side
    constexpr size_t kVertices = (kSide + 1) * (kSide + 1), kTriangles = 2 * kSide * kSide;
    std::vector<float> positions, normals, uvs, colors, raised;
    for (int y = 0; y <= kSide; ++y) {
        for (int x = 0; x <= kSide; ++x) {
            positions.insert(positions.end(), {static_cast<float>(x), static_cast<float>(y), 0.0f});
            normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
            uvs.insert(uvs.end(), {static_cast<float>(x) / kSide, static_cast<float>(y) / kSide});
            colors.insert(colors.end(), {1.0f, 0.5f, 0.25f, 1.0f});
            raised.insert(raised.end(), {0.0f, 0.0f, 1.0f});
        }
    }
    std::vector<uint16_t> indices;
    for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
            const auto corner = [&](int dx, int dy) {
                return static_cast<uint16_t>((y + dy) * (kSide + 1) + x + dx);
            };
            indices.insert(indices.end(), {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 0),
                                           corner(1, 1), corner(0, 1)});
        }
    }
    test::GltfDocument d;
    const int uvAccessor = d.floats(uvs, "VEC2");
    nlohmann::json attributes = {{"POSITION", d.positions(positions)},
                                 {"NORMAL", d.floats(normals, "VEC3")},
                                 {"TEXCOORD_0", uvAccessor},
                                 {"TEXCOORD_1", uvAccessor},
                                 {"COLOR_0", d.floats(colors, "VEC4")}};
    addOneTexelTexture(d);
    d.json["materials"] = {{{"normalTexture", {{"index", 0}}}}};
    d.json["meshes"] = {{{"primitives",
                          {{{"attributes", attributes},
                            {"indices", d.unsignedShorts(indices, "SCALAR")},
                            {"material", 0}}}}}};
    d.node({{"mesh", 0}});
    d.write(folder / "kept.gltf");
    const int target = d.floats(raised, "VEC3");
    d.json["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", target}}};
    d.json["meshes"][0]["weights"] = {1.0};
    d.write(folder / "morphed.gltf");

    const uint64_t kept =
        kTriangles * (sizeof(Triangle) + sizeof(TriangleShading) + 2 * sizeof(std::array<glm::vec4, 3>) +
                      sizeof(std::array<glm::vec2, 3>));
    const Scene scene = loadGltf((folder / "kept.gltf").string());
    ASSERT_EQ(scene.triangles.size(), kTriangles);
    EXPECT_EQ(scene.tangents.size(), kTriangles);
    EXPECT_EQ(scene.vertexColors.size(), kTriangles);
    EXPECT_EQ(scene.uv1.size(), kTriangles);
    // The image and the material take a few hundred bytes more.
    EXPECT_EQ(refusalUnder(folder / "kept.gltf", kept + 4096), "loaded");
    const std::string refused = refusalUnder(folder / "kept.gltf", kept);
    EXPECT_NE(refused.find("node 0 places mesh 0 1 time(s)"), std::string::npos) << refused;
    // The target's positions and the mapped coordinates, 5 floats a vertex, held for the rest of the load.
    const uint64_t morphed = kept + kVertices * 5 * sizeof(float);
    EXPECT_EQ(refusalUnder(folder / "morphed.gltf", morphed + 4096), "loaded");
    EXPECT_NE(refusalUnder(folder / "morphed.gltf", morphed)
                  .find("morph targets and skin influences would take " +
                        formatBytes(kVertices * 5 * sizeof(float))),
              std::string::npos)
        << refusalUnder(folder / "morphed.gltf", morphed);
}

TEST(GltfLoader, SharedMeshInstancesArePlacedPerNode) {
    const Scene scene = loadGltf(writeInstancedMeshes(test::temporaryFolder(), true).string());
    // Each node's mesh corners, placed by hand, in walk order (nodes 0 to 4, then 5 under 4).
    using Place = std::function<glm::dvec3(glm::dvec3)>;
    const std::vector<glm::dvec3> a = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<glm::dvec3> b = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    const std::vector<std::array<int, 3>> aFaces = {{0, 1, 2}}, bFaces = {{0, 1, 2}, {0, 2, 3}};
    struct Instance {
        const std::vector<glm::dvec3>* corners;
        const std::vector<std::array<int, 3>>* faces;
        uint32_t material;
        bool mirrored;
        Place place;
    };
    const std::vector<Instance> instances = {
        {&a, &aFaces, 0, false, [](glm::dvec3 p) { return p + glm::dvec3(4, 0, 0); }},
        {&b, &bFaces, 1, false, [](glm::dvec3 p) { return glm::dvec3(-p.y, p.x + 8, p.z); }},
        {&a, &aFaces, 0, false, [](glm::dvec3 p) { return 2.0 * p + glm::dvec3(0, 0, -4); }},
        {&b, &bFaces, 1, true, [](glm::dvec3 p) { return glm::dvec3(-p.x - 8, p.y, p.z); }},
        {&a, &aFaces, 0, false, [](glm::dvec3 p) { return glm::dvec3(p.x, -p.y, -p.z); }},
        {&b, &bFaces, 1, false, [](glm::dvec3 p) { return glm::dvec3(p.x + 1, -(p.y + 1), -(p.z + 1)); }},
    };
    std::vector<Triangle> expected;
    for (const Instance& instance : instances) {
        for (std::array<int, 3> face : *instance.faces) {
            if (instance.mirrored) std::swap(face[1], face[2]);
            auto corner = [&](int k) {
                return glm::vec3(instance.place((*instance.corners)[face[k]]) - scene.origin);
            };
            expected.push_back({corner(0), corner(1), corner(2), instance.material});
        }
    }
    ASSERT_EQ(scene.triangles.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        SCOPED_TRACE("triangle " + std::to_string(i));
        EXPECT_EQ(scene.triangles[i].v0, expected[i].v0);
        EXPECT_EQ(scene.triangles[i].v1, expected[i].v1);
        EXPECT_EQ(scene.triangles[i].v2, expected[i].v2);
        EXPECT_EQ(scene.triangles[i].material, expected[i].material);
    }
    // Mesh A's normals (0, 0, 1) follow each instance: turned over by the 180-degree rotation only.
    EXPECT_EQ(scene.shading[0].normal[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(scene.shading[3].normal[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(scene.shading[6].normal[0], glm::vec3(0, 0, -1));
}

TEST(GltfLoader, SharedMeshesEqualPerNodeCopies) {
    // Decoding a mesh once and placing it per node gives bit for bit what decoding a copy per node gives,
    // in the same order, with the same shading and materials.
    const auto folder = test::temporaryFolder();
    const Scene shared = loadGltf(writeInstancedMeshes(folder, true).string());
    const Scene copies = loadGltf(writeInstancedMeshes(folder, false).string());
    ASSERT_EQ(shared.triangles.size(), 9u);
    ASSERT_EQ(copies.triangles.size(), shared.triangles.size());
    EXPECT_EQ(shared.origin, copies.origin);
    const std::vector<uint32_t> materials = {0, 1, 1, 0, 1, 1, 0, 1, 1};  // A, B, A, B, A, B
    for (size_t i = 0; i < shared.triangles.size(); ++i) {
        SCOPED_TRACE("triangle " + std::to_string(i));
        EXPECT_EQ(shared.triangles[i].material, materials[i]);
        EXPECT_EQ(std::memcmp(&shared.triangles[i], &copies.triangles[i], sizeof(Triangle)), 0);
        EXPECT_EQ(std::memcmp(&shared.shading[i], &copies.shading[i], sizeof(TriangleShading)), 0);
    }
    EXPECT_EQ(shared.warnings, copies.warnings);
}

TEST(GltfLoader, VolumeAndTransmissionExtensions) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-AttenuationTest/AttenuationTest.glb");
    int volumes = 0, attenuating = 0;
    for (const Material& m : scene.materials) {
        volumes += m.hasVolume() && m.transmission > 0.0f;
        attenuating += std::isfinite(m.attenuationDistance);
    }
    EXPECT_GT(volumes, 0);
    EXPECT_GT(attenuating, 0);
}

TEST(GltfLoader, NvidiaCornellWarnsAboutItsVendorExtension) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("cornell-box-nvidia/cornellBox.gltf");
    bool named = false;
    for (const std::string& warning : scene.warnings)
        named |= warning.find("NV_materials_mdl") != std::string::npos;
    EXPECT_TRUE(named);
    EXPECT_FALSE(scene.emissiveTriangles.empty());
}

TEST(GltfLoader, OwnCornellBoxMatchesThePublishedData) {
    const Scene scene = loadGltf((test::sourceDir() / "scenes/cornell.gltf").string());
    EXPECT_EQ(scene.triangles.size(), 38u);  // 5 walls (ceiling in 4 parts), 2 blocks of 5 faces, the light
    EXPECT_EQ(scene.emissiveTriangles.size(), 2u);
    ASSERT_EQ(scene.cameras.size(), 1u);
    const Camera& camera = scene.cameras[0];
    EXPECT_NEAR(camera.yfov, 2.0 * std::atan(12.5 / 35.0), 1e-12);
    // Stored positions are relative to scene.origin (near the middle of the box).
    const glm::dvec3 eye = camera.position + scene.origin;
    EXPECT_NEAR(eye.x, 0.278, 1e-9);
    EXPECT_NEAR(eye.y, 0.273, 1e-9);
    EXPECT_NEAR(eye.z, -0.800, 1e-9);
    EXPECT_NEAR(camera.forward.z, 1.0, 1e-12);
    EXPECT_NEAR(camera.up.y, 1.0, 1e-12);
    // Box extents in metres: 556.0 x 548.8 x 559.2 mm, from (0, 0, 0).
    const glm::dvec3 lo = glm::dvec3(scene.bounds.min) + scene.origin,
                     hi = glm::dvec3(scene.bounds.max) + scene.origin;
    EXPECT_NEAR(lo.x, 0.0, 1e-6);
    EXPECT_NEAR(lo.y, 0.0, 1e-6);
    EXPECT_NEAR(lo.z, 0.0, 1e-6);
    EXPECT_NEAR(hi.x, 0.556, 1e-6);
    EXPECT_NEAR(hi.y, 0.5488, 1e-6);
    EXPECT_NEAR(hi.z, 0.5592, 1e-6);
    EXPECT_NEAR(scene.origin.x, 0.278, 1e-3);  // the walls' vertices' median, near the box's middle
    // The light faces down into the box.
    for (uint32_t index : scene.emissiveTriangles) {
        const Triangle& t = scene.triangles[index];
        EXPECT_LT(glm::cross(t.v1 - t.v0, t.v2 - t.v0).y, 0.0f);
    }
}

TEST(GltfLoader, OwnScenesLoad) {
    const Scene whitted = loadGltf((test::sourceDir() / "scenes/whitted.gltf").string());
    EXPECT_EQ(whitted.lights.size(), 1u);
    int mirrors = 0, glass = 0;
    for (const Material& m : whitted.materials) {
        mirrors += m.metallic == 1.0f && m.roughness == 0.0f;
        glass += m.transmission == 1.0f && m.hasVolume();
    }
    EXPECT_EQ(mirrors, 1);
    EXPECT_EQ(glass, 1);
    const Scene lights = loadGltf((test::sourceDir() / "scenes/lights.gltf").string());
    ASSERT_EQ(lights.lights.size(), 3u);
    EXPECT_EQ(lights.lights[0].type, LightType::Point);
    EXPECT_EQ(lights.lights[1].type, LightType::Spot);
    EXPECT_EQ(lights.lights[2].type, LightType::Directional);
    EXPECT_NEAR(lights.lights[1].direction.y, -1.0, 1e-9);  // the spot points down
}

TEST(CameraSelection, DefaultCameraFramesTheScene) {
    Aabb bounds;
    bounds.grow(glm::vec3(-1.0f, -2.0f, -3.0f));
    bounds.grow(glm::vec3(3.0f, 2.0f, 1.0f));
    for (double aspect : {0.5, 1.0, 2.0}) {
        const Camera camera = frameBounds(bounds, aspect);
        EXPECT_TRUE(camera.generated);
        // The bounding sphere's silhouette fits both fields of view.
        const glm::dvec3 center(1.0, 0.0, -1.0);
        const double radius = glm::length(glm::dvec3(2.0, 2.0, 2.0));
        const double distance = glm::length(center - camera.position);
        const double halfAngle = std::asin(radius / distance);
        const double halfY = 0.5 * camera.yfov;
        const double halfX = std::atan(std::tan(halfY) * aspect);
        EXPECT_LE(halfAngle, std::min(halfX, halfY) + 1e-9) << aspect;
    }
}

}  // namespace
}  // namespace vkrt
