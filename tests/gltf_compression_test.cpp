// Compressed and quantized meshes (EXT_meshopt_compression, KHR_draco_mesh_compression,
// KHR_mesh_quantization) load as the same triangles as the plain file they were made from. The compressed
// files are made here, by the libraries' own encoders (meshoptimizer, Draco), from one small mesh.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <stb/stb_image_write.h>
#include <webp/encode.h>
#include <nlohmann/json.hpp>

#include "app/render_policy.h"
#include "cpu/reference_renderer.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_schema.h"
#include "scene/scene_error.h"
#include "support/gltf_document.h"
#include "support/render_both.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using nlohmann::json;

// A bumpy 7 x 7 grid: 49 vertices with positions and unit normals, 72 triangles.
struct Grid {
    std::vector<float> positions, normals;  // 3 per vertex
    std::vector<uint32_t> indices;
};

Grid grid() {
    Grid g;
    const int n = 7;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const float h = 0.3f * std::sin(1.3f * x) * std::cos(0.7f * y);
            g.positions.insert(g.positions.end(), {0.5f * x - 1.5f, h, 0.5f * y - 1.5f});
            const float nx = -0.39f * std::cos(1.3f * x) * std::cos(0.7f * y),
                        nz = 0.21f * std::sin(1.3f * x) * std::sin(0.7f * y);
            const float length = std::sqrt(nx * nx + 1.0f + nz * nz);
            g.normals.insert(g.normals.end(), {nx / length, 1.0f / length, nz / length});
        }
    }
    for (int y = 0; y + 1 < n; ++y) {
        for (int x = 0; x + 1 < n; ++x) {
            const uint32_t a = y * n + x, b = a + 1, c = a + n, d = c + 1;
            g.indices.insert(g.indices.end(), {a, c, b, b, c, d});
        }
    }
    return g;
}

std::string bytesOf(const void* data, size_t size) {
    return std::string(static_cast<const char*>(data), size);
}

// A one-mesh document over `accessors` and `views` (the mesh: accessor 0 positions, 1 normals, 2 indices).
json document(json accessors, json views, json buffers, json extensions = json::array()) {
    const json primitive = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}};
    json d = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}},
              {"meshes", {{{"primitives", {primitive}}}}},
              {"accessors", accessors},
              {"bufferViews", views},
              {"buffers", buffers}};
    if (!extensions.empty()) d["extensionsUsed"] = d["extensionsRequired"] = extensions;
    return d;
}

json floatAccessor(int view, size_t count, const char* type) {
    return {{"bufferView", view}, {"componentType", 5126}, {"count", count}, {"type", type}};
}

json gridAccessors(const Grid& g, int firstView) {
    json positions = floatAccessor(firstView, g.positions.size() / 3, "VEC3");
    positions["min"] = {-1.5, -0.3, -1.5};
    positions["max"] = {1.5, 0.3, 1.5};
    const json indices = {{"bufferView", firstView + 2},
                          {"componentType", 5125},
                          {"count", g.indices.size()},
                          {"type", "SCALAR"}};
    return {positions, floatAccessor(firstView + 1, g.normals.size() / 3, "VEC3"), indices};
}

// The plain file: float positions and normals, 32-bit indices.
std::filesystem::path writePlain(const std::filesystem::path& folder, const Grid& g) {
    const std::string bin = bytesOf(g.positions.data(), g.positions.size() * 4) +
                            bytesOf(g.normals.data(), g.normals.size() * 4) +
                            bytesOf(g.indices.data(), g.indices.size() * 4);
    test::writeText(folder / "plain.bin", bin);
    const size_t p = g.positions.size() * 4, n = g.normals.size() * 4, i = g.indices.size() * 4;
    const json views = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", p}},
                        {{"buffer", 0}, {"byteOffset", p}, {"byteLength", n}},
                        {{"buffer", 0}, {"byteOffset", p + n}, {"byteLength", i}}};
    const std::filesystem::path file = folder / "plain.gltf";
    test::writeText(
        file,
        document(gridAccessors(g, 0), views, {{{"uri", "plain.bin"}, {"byteLength", bin.size()}}}).dump());
    return file;
}

// `document` and `bin` as a GLB file.
void writeGlb(const std::filesystem::path& file, const json& document, const std::string& bin) {
    test::writeText(file, glbFile(document.dump(), bin));
}

// The grid's triangles, each corner's position and normal, in an order of their own: a decoder may reorder
// triangles (Draco does) and turn their corners. Each is turned to start at its first corner in grid order
// (keeping its winding), and they are sorted by their corners' grid cells (x and z are multiples of 0.5).
using Corner = std::array<float, 6>;
std::vector<std::array<Corner, 3>> trianglesOf(const Scene& scene) {
    auto cell = [](const Corner& c) {
        return std::make_pair(std::lround(2.0f * c[0]), std::lround(2.0f * c[2]));
    };
    std::vector<std::array<Corner, 3>> triangles;
    for (size_t t = 0; t < scene.triangles.size(); ++t) {
        const glm::vec3 v[3] = {scene.triangles[t].v0, scene.triangles[t].v1, scene.triangles[t].v2};
        std::array<Corner, 3> corners;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 world = glm::dvec3(v[k]) + scene.origin;
            const glm::vec3 normal = scene.shading[t].normal[k];
            corners[k] = {float(world.x), float(world.y), float(world.z), normal.x, normal.y, normal.z};
        }
        std::rotate(corners.begin(),
                    std::min_element(corners.begin(), corners.end(),
                                     [&](const Corner& a, const Corner& b) { return cell(a) < cell(b); }),
                    corners.end());
        triangles.push_back(corners);
    }
    std::sort(triangles.begin(), triangles.end(), [&](const auto& a, const auto& b) {
        return std::make_tuple(cell(a[0]), cell(a[1]), cell(a[2])) <
               std::make_tuple(cell(b[0]), cell(b[1]), cell(b[2]));
    });
    return triangles;
}

void expectSameTriangles(const Scene& expected, const Scene& actual, float positionTolerance,
                         float normalTolerance) {
    const auto a = trianglesOf(expected), b = trianglesOf(actual);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), 72u);
    for (size_t t = 0; t < a.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 6; ++c) {
                EXPECT_NEAR(a[t][k][c], b[t][k][c], c < 3 ? positionTolerance : normalTolerance)
                    << "triangle " << t << " corner " << k << " component " << c;
            }
        }
    }
}

// The grid with every view compressed by meshoptimizer (positions as they are, normals through the
// octahedral filter into 8-bit pairs, indices by the triangle codec) in `compressed`, and the views over a
// fallback buffer with no data.
struct MeshoptGrid {
    json document;
    std::string compressed;
};

MeshoptGrid meshoptGrid(const Grid& g) {
    const size_t count = g.positions.size() / 3;
    auto encodeVertices = [&](const void* vertices, size_t stride) {
        std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(count, stride));
        out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), vertices, count, stride));
        return bytesOf(out.data(), out.size());
    };
    std::vector<float> normals4;
    for (size_t v = 0; v < count; ++v)
        normals4.insert(normals4.end(), {g.normals[3 * v], g.normals[3 * v + 1], g.normals[3 * v + 2], 0.0f});
    std::vector<int8_t> octahedral(4 * count);
    meshopt_encodeFilterOct(octahedral.data(), count, 4, 8, normals4.data());
    std::vector<unsigned char> indices(meshopt_encodeIndexBufferBound(g.indices.size(), count));
    indices.resize(
        meshopt_encodeIndexBuffer(indices.data(), indices.size(), g.indices.data(), g.indices.size()));

    const std::string blocks[3] = {encodeVertices(g.positions.data(), 12),
                                   encodeVertices(octahedral.data(), 4),
                                   bytesOf(indices.data(), indices.size())};
    const size_t strides[3] = {12, 4, 4}, counts[3] = {count, count, g.indices.size()};
    const char* modes[3] = {"ATTRIBUTES", "ATTRIBUTES", "TRIANGLES"};
    MeshoptGrid result;
    json views = json::array();
    size_t fallbackSize = 0;
    for (int k = 0; k < 3; ++k) {
        json extension = {{"buffer", 0},
                          {"byteOffset", result.compressed.size()},
                          {"byteLength", blocks[k].size()},
                          {"byteStride", strides[k]},
                          {"count", counts[k]},
                          {"mode", modes[k]}};
        if (k == 1) extension["filter"] = "OCTAHEDRAL";
        json view = {{"buffer", 1},
                     {"byteOffset", fallbackSize},
                     {"byteLength", strides[k] * counts[k]},
                     {"extensions", {{"EXT_meshopt_compression", extension}}}};
        if (k < 2) view["byteStride"] = strides[k];
        views.push_back(view);
        fallbackSize += strides[k] * counts[k];
        result.compressed += blocks[k];
        result.compressed.resize((result.compressed.size() + 3) / 4 * 4, '\0');
    }
    json accessors = gridAccessors(g, 0);
    accessors[1] = {
        {"bufferView", 1}, {"componentType", 5120}, {"normalized", true}, {"count", count}, {"type", "VEC3"}};
    const json buffers = {
        {{"byteLength", result.compressed.size()}},
        {{"byteLength", fallbackSize}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    result.document = document(accessors, views, buffers, {"EXT_meshopt_compression"});
    return result;
}

TEST(GltfCompression, MeshoptViewsDecodeToThePlainMesh) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    const Scene plain = loadGltf(writePlain(folder, g).string());
    MeshoptGrid compressed = meshoptGrid(g);

    // A GLB whose binary chunk holds the compressed data (the fallback buffer, larger, has none).
    writeGlb(folder / "meshopt.glb", compressed.document, compressed.compressed);
    // The same as .gltf with the data in a file of its own.
    compressed.document["buffers"][0]["uri"] = "meshopt.bin";
    test::writeText(folder / "meshopt.bin", compressed.compressed);
    test::writeText(folder / "meshopt.gltf", compressed.document.dump());
    for (const char* name : {"meshopt.glb", "meshopt.gltf"}) {
        SCOPED_TRACE(name);
        // Positions are exact; normals went through 8-bit octahedral pairs.
        expectSameTriangles(plain, loadGltf((folder / name).string()), 0.0f, 0.02f);
    }
}

TEST(GltfCompression, MeshoptDataThatDoesNotFitIsRefused) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    auto expectRefused = [&](const MeshoptGrid& file, const std::string& expected) {
        writeGlb(folder / "bad.glb", file.document, file.compressed);
        try {
            loadGltf((folder / "bad.glb").string());
            ADD_FAILURE() << "loaded; expected " << expected;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    MeshoptGrid truncated = meshoptGrid(g);
    truncated.document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 20;
    expectRefused(truncated, "does not decode");
    MeshoptGrid huge = meshoptGrid(g);
    huge.document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 1u << 28;
    expectRefused(huge, "cannot come from");
    MeshoptGrid outside = meshoptGrid(g);
    outside.document["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 1u << 20;
    expectRefused(outside, "of buffer 0");
    MeshoptGrid mode = meshoptGrid(g);
    mode.document["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["mode"] = "STRIPS";
    expectRefused(mode, "unknown mode");
}

// The grid as one Draco-compressed buffer view (positions, normals); lossless unless `quantize`.
std::string dracoGrid(const Grid& g, bool quantize, int& positionId, int& normalId) {
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(static_cast<int>(g.indices.size() / 3));
    const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int normal = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
    for (size_t f = 0; f < g.indices.size() / 3; ++f) {
        const uint32_t* corner = &g.indices[3 * f];
        builder.SetAttributeValuesForFace(position, draco::FaceIndex(f), &g.positions[3 * corner[0]],
                                          &g.positions[3 * corner[1]], &g.positions[3 * corner[2]]);
        builder.SetAttributeValuesForFace(normal, draco::FaceIndex(f), &g.normals[3 * corner[0]],
                                          &g.normals[3 * corner[1]], &g.normals[3 * corner[2]]);
    }
    std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    positionId = static_cast<int>(mesh->attribute(position)->unique_id());
    normalId = static_cast<int>(mesh->attribute(normal)->unique_id());
    draco::Encoder encoder;
    if (quantize) {
        encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
        encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    }
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
    return std::string(buffer.data(), buffer.size());
}

// A document whose one primitive is `size` bytes of Draco data; its accessors have no buffer views.
json dracoDocument(const Grid& g, size_t size, int positionId, int normalId) {
    json accessors = gridAccessors(g, 0);
    for (json& accessor : accessors) accessor.erase("bufferView");
    json d = document(accessors, {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", size}}},
                      {{{"byteLength", (size + 3) / 4 * 4}}}, {"KHR_draco_mesh_compression"});
    d["meshes"][0]["primitives"][0]["extensions"] = {
        {"KHR_draco_mesh_compression",
         {{"bufferView", 0}, {"attributes", {{"POSITION", positionId}, {"NORMAL", normalId}}}}}};
    return d;
}

TEST(GltfCompression, DracoPrimitivesDecodeToThePlainMesh) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    const Scene plain = loadGltf(writePlain(folder, g).string());
    for (const bool quantize : {false, true}) {
        SCOPED_TRACE(quantize ? "quantized" : "lossless");
        int positionId = -1, normalId = -1;
        const std::string data = dracoGrid(g, quantize, positionId, normalId);
        writeGlb(folder / "draco.glb", dracoDocument(g, data.size(), positionId, normalId), data);
        // Exact when not quantized; 14 bits over the grid's 3-unit width are 2e-4.
        expectSameTriangles(plain, loadGltf((folder / "draco.glb").string()), quantize ? 2e-4f : 0.0f,
                            quantize ? 0.01f : 1e-6f);
    }
}

TEST(GltfCompression, DracoDataThatDoesNotDecodeIsRefused) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    int positionId = -1, normalId = -1;
    const std::string data = dracoGrid(g, false, positionId, normalId);
    auto expectRefused = [&](const json& document, const std::string& bytes, const std::string& expected) {
        writeGlb(folder / "bad.glb", document, bytes);
        try {
            loadGltf((folder / "bad.glb").string());
            ADD_FAILURE() << "loaded; expected " << expected;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    expectRefused(dracoDocument(g, data.size() / 2, positionId, normalId), data, "does not decode");
    expectRefused(dracoDocument(g, data.size(), positionId, normalId + 7), data, "has no attribute");
    json noSuchSlot = dracoDocument(g, data.size(), positionId, normalId);
    noSuchSlot["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]
              ["TEXCOORD_0"] = normalId;
    expectRefused(noSuchSlot, data, "no such attribute");
}

// A file of the grid with its positions as 16-bit integers (`quantized`: four a vertex, the last padding, so
// 8 bytes a vertex), its normals and indices as they are: the accessors (the positions' to be completed by
// the caller) and the views, with its binary in `bin`.
template <typename Integer>
json quantizedGridFile(const Grid& g, const std::vector<Integer>& quantized, std::string& bin,
                       int componentType) {
    static_assert(sizeof(Integer) == 2);
    bin = bytesOf(quantized.data(), quantized.size() * 2) + bytesOf(g.normals.data(), g.normals.size() * 4) +
          bytesOf(g.indices.data(), g.indices.size() * 4);
    const size_t p = quantized.size() * 2, n = g.normals.size() * 4;
    const json views = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", p}, {"byteStride", 8}},
                        {{"buffer", 0}, {"byteOffset", p}, {"byteLength", n}},
                        {{"buffer", 0}, {"byteOffset", p + n}, {"byteLength", g.indices.size() * 4}}};
    json accessors = gridAccessors(g, 0);
    accessors[0]["componentType"] = componentType;
    return document(accessors, views, json::array({{{"byteLength", bin.size()}}}));
}

TEST(GltfCompression, IntegerPositionsNeedMeshQuantization) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    const Scene plain = loadGltf(writePlain(folder, g).string());
    // Positions in hundredths as 16-bit integers (padded to 8 bytes), scaled back by the node.
    std::vector<int16_t> quantized;
    for (size_t v = 0; v < g.positions.size() / 3; ++v) {
        for (int c = 0; c < 3; ++c)
            quantized.push_back(static_cast<int16_t>(std::lround(100.0f * g.positions[3 * v + c])));
        quantized.push_back(0);
    }
    std::string bin;
    json file = quantizedGridFile(g, quantized, bin, 5122);
    file["accessors"][0]["min"] = {-150, -30, -150};
    file["accessors"][0]["max"] = {150, 30, 150};
    file["nodes"][0]["scale"] = {0.01, 0.01, 0.01};
    writeGlb(folder / "plain-integers.glb", file, bin);
    try {
        loadGltf((folder / "plain-integers.glb").string());
        ADD_FAILURE() << "integer positions loaded without KHR_mesh_quantization";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("KHR_mesh_quantization"), std::string::npos) << e.what();
    }
    file["extensionsUsed"] = file["extensionsRequired"] = {"KHR_mesh_quantization"};
    writeGlb(folder / "quantized.glb", file, bin);
    expectSameTriangles(plain, loadGltf((folder / "quantized.glb").string()), 0.006f, 1e-6f);
}

// Normalized integer positions (gltfpack's output): the accessor's min and max are the stored integers (glTF
// 2.0 section 3.6.2.5), which the scene's re-centring must normalize too. Taken as positions, they put the
// centre 65535 times the node's scale away, and every float position relative to it lost its low digits.
TEST(GltfCompression, NormalizedPositionsAreCentredByTheirNormalizedBounds) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    const Scene plain = loadGltf(writePlain(folder, g).string());
    // Positions over [-1.5, 1.5] as unsigned 16-bit fractions of [0, 1] (padded to 8 bytes); the node scales
    // them by 3 and moves them by -1.5.
    std::vector<uint16_t> quantized;
    for (size_t v = 0; v < g.positions.size() / 3; ++v) {
        for (int c = 0; c < 3; ++c)
            quantized.push_back(
                static_cast<uint16_t>(std::lround((g.positions[3 * v + c] + 1.5f) / 3.0f * 65535.0f)));
        quantized.push_back(0);
    }
    std::string bin;
    json file = quantizedGridFile(g, quantized, bin, 5123);
    file["accessors"][0]["normalized"] = true;
    file["accessors"][0]["min"] = {0, 26214, 0};  // y from -0.3 to 0.3
    file["accessors"][0]["max"] = {65535, 39321, 65535};
    file["nodes"][0]["scale"] = {3.0, 3.0, 3.0};
    file["nodes"][0]["translation"] = {-1.5, -1.5, -1.5};
    file["extensionsUsed"] = file["extensionsRequired"] = {"KHR_mesh_quantization"};
    writeGlb(folder / "normalized.glb", file, bin);
    const Scene quantizedScene = loadGltf((folder / "normalized.glb").string());
    EXPECT_LT(glm::length(quantizedScene.origin - plain.origin), 1e-3) << quantizedScene.origin.x;
    expectSameTriangles(plain, quantizedScene, 1e-4f, 1e-6f);
}

// A triangle (quad.bin: writeQuadData) whose material shows textures[0], `texture`, over `images`.
json texturedTriangle(json texture, json images, bool required) {
    json positions = floatAccessor(0, 3, "VEC3");
    positions["min"] = {0, 0, 0};
    positions["max"] = {1, 1, 0};
    json d = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}},
              {"meshes",
               {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"material", 0}}}}}}},
              {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
              {"textures", {texture}},
              {"images", images},
              {"accessors", {positions, floatAccessor(1, 3, "VEC2")}},
              {"bufferViews",
               {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 24}}}},
              {"buffers", {{{"uri", "quad.bin"}, {"byteLength", 60}}}}};
    d["extensionsUsed"] = {"EXT_texture_webp"};
    if (required) d["extensionsRequired"] = {"EXT_texture_webp"};
    return d;
}

void writeQuadData(const std::filesystem::path& folder) {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uvs[6] = {0, 1, 1, 1, 0, 0};
    test::writeText(folder / "quad.bin", bytesOf(positions, sizeof(positions)) + bytesOf(uvs, sizeof(uvs)));
}

TEST(GltfCompression, WebpTexturesDecodeToTheirPixels) {
    const auto folder = test::temporaryFolder();
    writeQuadData(folder);
    // A 4 x 3 image, every pixel its own colour and alpha, encoded losslessly.
    std::vector<uint8_t> pixels;
    for (int i = 0; i < 12; ++i) {
        pixels.insert(pixels.end(),
                      {uint8_t(20 * i), uint8_t(255 - 7 * i), uint8_t(i * i), uint8_t(255 - i)});
    }
    uint8_t* encoded = nullptr;
    const size_t size = WebPEncodeLosslessRGBA(pixels.data(), 4, 3, 16, &encoded);
    ASSERT_GT(size, 0u);
    test::writeText(folder / "texture.webp", bytesOf(encoded, size));
    // The fallback for viewers without the extension: one grey pixel.
    const uint8_t grey[3] = {128, 128, 128};
    ASSERT_TRUE(stbi_write_png((folder / "fallback.png").string().c_str(), 1, 1, 3, grey, 3));

    const json withFallback = {{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}};
    const json webpOnly = {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}};
    // Also embedded as a data URI of type image/webp, which tinygltf did not take for one (it looked for a
    // file of that name).
    const std::string dataUri =
        "data:image/webp;base64," + test::base64(std::vector<uint8_t>(encoded, encoded + size));
    const json cases[3] = {
        texturedTriangle(withFallback, {{{"uri", "fallback.png"}}, {{"uri", "texture.webp"}}}, false),
        texturedTriangle(webpOnly, {{{"uri", "texture.webp"}}}, true),
        texturedTriangle(webpOnly, {{{"uri", dataUri}}}, true)};
    WebPFree(encoded);
    for (const json& document : cases) {
        test::writeText(folder / "quad.gltf", document.dump());
        const Scene scene = loadGltf((folder / "quad.gltf").string());
        ASSERT_EQ(scene.textures.size(), 1u);
        EXPECT_EQ(scene.textures[0].width, 4);
        EXPECT_EQ(scene.textures[0].height, 3);
        EXPECT_EQ(*scene.textures[0].rgba, pixels);
    }
    // Bytes that claim to be WebP and are not.
    test::writeText(folder / "texture.webp",
                    std::string("RIFF\x10\0\0\0WEBPVP8L", 16) + std::string(8, '\x7f'));
    test::writeText(folder / "quad.gltf", cases[1].dump());
    try {
        loadGltf((folder / "quad.gltf").string());
        ADD_FAILURE() << "a broken WebP image loaded";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("WebP"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

// An image vkrt cannot decode stops the load only where a texture it reads uses it: not behind an optional
// extension's fallback (a KHR_texture_basisu texture's KTX2 image, its core source a PNG), nor unused.
TEST(GltfCompression, ImagesThatDoNotDecodeFailOnlyWhereUsed) {
    const auto folder = test::temporaryFolder();
    writeQuadData(folder);
    const uint8_t grey[3] = {128, 128, 128};
    ASSERT_TRUE(stbi_write_png((folder / "fallback.png").string().c_str(), 1, 1, 3, grey, 3));
    test::writeText(folder / "logo.ktx2",
                    std::string("\xabKTX 20\xbb\r\n\x1a\n", 12) + std::string(64, '\0'));
    const json basisu = {{"source", 0}, {"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}};
    json withFallback = texturedTriangle(basisu, {{{"uri", "fallback.png"}}, {{"uri", "logo.ktx2"}}}, false);
    withFallback["extensionsUsed"] = {"KHR_texture_basisu"};
    json unused =
        texturedTriangle({{"source", 0}}, {{{"uri", "fallback.png"}}, {{"uri", "logo.ktx2"}}}, false);
    for (const json& document : {withFallback, unused}) {
        test::writeText(folder / "quad.gltf", document.dump());
        const Scene scene = loadGltf((folder / "quad.gltf").string());
        ASSERT_EQ(scene.textures.size(), 1u);
        EXPECT_EQ(*scene.textures[0].rgba, std::vector<uint8_t>({128, 128, 128, 255}));
    }
    // Used, it fails, saying why.
    json used = texturedTriangle({{"source", 1}}, {{{"uri", "fallback.png"}}, {{"uri", "logo.ktx2"}}}, false);
    test::writeText(folder / "quad.gltf", used.dump());
    try {
        loadGltf((folder / "quad.gltf").string());
        ADD_FAILURE() << "a KTX2 image was used";
    } catch (const SceneError& e) {
        EXPECT_NE(
            std::string(e.what()).find("image 1 ('logo.ktx2') could not be decoded: it is not an image vkrt "
                                       "can decode"),
            std::string::npos)
            << e.what();
    }
}

// tinygltf keeps an extension's integers as 32-bit ints, so a number 2^32 larger than a valid one was read as
// that one: the file loaded other data than it named, without a word. Each such number is refused, named by
// its JSON path and shown as the file gives it.
TEST(GltfCompression, ExtensionIntegersBeyond32BitsAreRefused) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    constexpr uint64_t kWrap = uint64_t{1} << 32;
    auto expectRefused = [&](const std::filesystem::path& file, const std::string& where, uint64_t value) {
        try {
            loadGltf(file.string());
            ADD_FAILURE() << "loaded; expected " << where << " to be refused";
        } catch (const SceneError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(where + ": "), std::string::npos) << message;
            EXPECT_NE(message.find(std::to_string(value)), std::string::npos) << message;
        }
    };
    for (const char* key : {"buffer", "byteOffset", "byteLength", "byteStride", "count"}) {
        SCOPED_TRACE(key);
        MeshoptGrid wrapped = meshoptGrid(g);
        json& extension = wrapped.document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"];
        const uint64_t value = extension[key].get<uint64_t>() + kWrap;
        extension[key] = value;
        writeGlb(folder / "meshopt.glb", wrapped.document, wrapped.compressed);
        expectRefused(folder / "meshopt.glb",
                      std::string("bufferViews[0].extensions.EXT_meshopt_compression.") + key, value);
    }

    int positionId = -1, normalId = -1;
    const std::string data = dracoGrid(g, false, positionId, normalId);
    const std::string draco = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    json view = dracoDocument(g, data.size(), positionId, normalId);
    view["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = kWrap;
    writeGlb(folder / "draco.glb", view, data);
    expectRefused(folder / "draco.glb", draco + ".bufferView", kWrap);
    json id = dracoDocument(g, data.size(), positionId, normalId);
    id["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["NORMAL"] =
        normalId + kWrap;
    writeGlb(folder / "draco.glb", id, data);
    expectRefused(folder / "draco.glb", draco + ".attributes.NORMAL", normalId + kWrap);

    // A WebP source of 2^32 read as image 0, a PNG.
    writeQuadData(folder);
    const uint8_t grey[3] = {128, 128, 128};
    ASSERT_TRUE(stbi_write_png((folder / "grey.png").string().c_str(), 1, 1, 3, grey, 3));
    const json webp = {{"extensions", {{"EXT_texture_webp", {{"source", kWrap}}}}}};
    test::writeText(folder / "quad.gltf", texturedTriangle(webp, {{{"uri", "grey.png"}}}, true).dump());
    expectRefused(folder / "quad.gltf", "textures[0].extensions.EXT_texture_webp.source", kWrap);
}

// Draco's decoder allocates for the triangles its header declares before it reads them: the grid's data with
// 10^8 triangles declared (and as many connectivity symbols, which Draco checks against them), 1 KB, had it
// take 2.4 GB over 10 s, whatever memory the options allowed. The declared count is checked against the
// indices accessor's (which glTF requires to match), and what decoding it takes against the memory allowed,
// before anything is decoded.
TEST(GltfCompression, DracoTrianglesAreBoundedBeforeDecoding) {
    const auto folder = test::temporaryFolder();
    const Grid g = grid();
    int positionId = -1, normalId = -1;
    const std::string data = dracoGrid(g, false, positionId, normalId);
    // The header (Draco 2.2; a mesh, by edgebreaker): 11 bytes, the traversal's type, then as varints the
    // vertex count (49), the triangle count (72), one byte, and the symbol count (at most 72).
    ASSERT_EQ(data.substr(0, 5), "DRACO");
    ASSERT_EQ(data[7], 1);
    ASSERT_EQ(data[8], 1);
    ASSERT_EQ(data[12], 49);
    ASSERT_EQ(data[13], 72);
    const std::string hundredMillion = "\x80\xc2\xd7\x2f";  // 10^8 as a varint
    const std::string bomb =
        data.substr(0, 13) + hundredMillion + data[14] + hundredMillion + data.substr(16);
    auto expectRefused = [&](const json& document, const LoadOptions& options, const std::string& expected) {
        writeGlb(folder / "bomb.glb", document, bomb);
        try {
            loadGltf((folder / "bomb.glb").string(), options);
            ADD_FAILURE() << "loaded; expected " << expected;
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    expectRefused(
        dracoDocument(g, bomb.size(), positionId, normalId), LoadOptions(),
        "KHR_draco_mesh_compression: the compressed data holds 100000000 triangles, and its indices "
        "accessor declares 216 indices");
    json declared = dracoDocument(g, bomb.size(), positionId, normalId);
    declared["accessors"][2]["count"] = 300000000;
    LoadOptions limited;
    limited.maxSceneBytes = uint64_t{256} << 20;
    limited.memorySource = "--max-memory";
    expectRefused(declared, limited, "of host memory, and 256 MiB is available (--max-memory)");
}

// The scene in `file` rendered by the CPU reference at 32 x 32 and 16 samples per pixel.
Image cpuImage(const std::string& file) {
    const Scene scene = loadGltf((test::sourceDir() / file).string());
    RenderRequest request;
    request.settings.width = request.settings.height = 32;
    request.settings.samplesPerPixel = 16;
    const RenderSetup setup = resolveRender(request, scene);
    return ReferenceRenderer(scene, test::bvhFor(scene), setup.camera, setup.settings).render().image;
}

// Its channel means.
glm::dvec3 meanColour(const std::string& file) {
    const Image image = cpuImage(file);
    glm::dvec3 mean(0.0);
    for (const glm::vec3& pixel : image.pixels) mean += glm::dvec3(pixel) / double(image.pixels.size());
    return mean;
}

// scenes/cornell-meshopt.glb is gltfpack's compressed cornell.gltf (14-bit positions, 8-bit normals,
// meshoptimizer's codecs), scenes/cornell-draco.glb tools/pack_scene's (Draco, 14-bit positions, 10-bit
// normals). Both render as the original does.
TEST(GltfCompression, CompressedCornellBoxesRenderAsTheOriginal) {
    const glm::dvec3 original = meanColour("scenes/cornell.gltf");
    for (const char* file : {"scenes/cornell-meshopt.glb", "scenes/cornell-draco.glb"}) {
        SCOPED_TRACE(file);
        const glm::dvec3 mean = meanColour(file);
        // Nearly the same geometry: channel means within 1% (seen: 0.02% for meshoptimizer's, 0.2% for
        // Draco's, which orders the triangles, and so the emitters light samples pick, its own way), where a
        // wall's colour lost would move them by more than a tenth.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], original[c], 0.01 * original[c]) << "channel " << c;
    }
}

// scenes/textures-webp.glb is tools/pack_scene's textures.gltf with every image as lossless WebP: the same
// texels, so the same image, bit for bit.
TEST(GltfCompression, WebpTexturesSceneRendersAsTheOriginal) {
    const Image original = cpuImage("scenes/textures.gltf"), webp = cpuImage("scenes/textures-webp.glb");
    EXPECT_EQ(webp.pixels, original.pixels);
}

}  // namespace
}  // namespace vkrt
