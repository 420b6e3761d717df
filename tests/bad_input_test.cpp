// Malformed input: each class gets one clear error naming the file and the problem, exit code 2, no
// crash and no output file.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "image/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"
#include "support/gltf_document.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using nlohmann::json;

using test::base64;

std::filesystem::path fileFor(const std::filesystem::path& folder, std::string name) {
    std::replace(name.begin(), name.end(), ' ', '-');
    return folder / (name + ".gltf");
}

// One triangle: 3 float positions (36 bytes) then 3 uint16 indices (6 bytes, padded to 8).
std::vector<uint8_t> triangleBytes(float firstX = 0.0f) {
    const float positions[9] = {firstX, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t indices[4] = {0, 1, 2, 0};
    std::vector<uint8_t> bytes(44);
    std::memcpy(bytes.data(), positions, 36);
    std::memcpy(bytes.data() + 36, indices, 8);
    return bytes;
}

json validTriangle(const std::vector<uint8_t>& bytes = triangleBytes()) {
    return json{
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
          {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
          {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
        {"buffers",
         {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
    };
}

// The one triangle, plus an animation of node 0's translation with keys at `times` (2 keys, 2 values).
json animatedTriangle(float firstTime, float secondTime, int valueCount = 2, float last = 0.0f) {
    std::vector<uint8_t> bytes = triangleBytes();
    const float keys[2] = {firstTime, secondTime};
    const float values[6] = {0, 0, 0, 1, last, last};
    bytes.resize(44 + 8 + 24);
    std::memcpy(bytes.data() + 44, keys, 8);
    std::memcpy(bytes.data() + 52, values, 24);
    json d = validTriangle(bytes);
    d["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    d["accessors"].push_back(
        {{"bufferView", 3}, {"componentType", 5126}, {"count", valueCount}, {"type", "VEC3"}});
    d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 44}, {"byteLength", 8}});
    d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 52}, {"byteLength", 24}});
    d["animations"] = {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                        {"samplers", {{{"input", 2}, {"output", 3}}}}}};
    d["scenes"][0]["extras"] = {{"shutter", {0.0, 1.0}}};
    return d;
}

struct BadCase {
    const char* name;
    std::function<void(const std::filesystem::path& folder, std::filesystem::path& file)> make;
    const char* expected;  // a phrase the one-line error must contain
};

void writeJson(const std::filesystem::path& file, const json& document) {
    test::writeText(file, document.dump());
}

std::vector<BadCase> badCases() {
    return {
        {"missing file", [](auto& folder, auto& file) { file = folder / "does-not-exist.gltf"; },
         "cannot open"},
        {"malformed JSON",
         [](auto&, auto& file) { test::writeText(file, "{\"asset\": {\"version\": \"2.0\"}, "); }, ""},
        {"wrong JSON type",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][0]["count"] = "three";
             writeJson(file, d);
         },
         "count"},
        {"missing external buffer",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["buffers"][0]["uri"] = "missing.bin";
             writeJson(file, d);
         },
         "missing.bin"},
        {"short buffer",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["bufferViews"][1]["byteLength"] = 100;  // past the 44-byte buffer
             writeJson(file, d);
         },
         "bufferViews[1]: bytes [36, 136) lie outside buffer 0's 44"},
        {"accessor overflow",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][0]["count"] = 4;  // 4 VEC3 floats need 48 bytes, the view has 36
             writeJson(file, d);
         },
         "overflows"},
        {"accessor count far beyond its data",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][0]["count"] = 2147483647;  // read before checking, 24 GiB
             writeJson(file, d);
         },
         "overflows"},
        {"index out of range",
         [](auto&, auto& file) {
             std::vector<uint8_t> bytes = triangleBytes();
             const uint16_t bad = 7;
             std::memcpy(bytes.data() + 40, &bad, 2);
             writeJson(file, validTriangle(bytes));
         },
         "out of range"},
        {"non-finite position",
         [](auto&, auto& file) {
             writeJson(file, validTriangle(triangleBytes(std::numeric_limits<float>::quiet_NaN())));
         },
         "non-finite"},
        {"infinite position",
         [](auto&, auto& file) {
             writeJson(file, validTriangle(triangleBytes(std::numeric_limits<float>::infinity())));
         },
         "non-finite"},
        {"sphere without radius",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"].push_back({{"extensions", {{"VKRT_sphere", json::object()}}}});
             d["scenes"][0]["nodes"].push_back(1);
             writeJson(file, d);
         },
         "radius"},
        {"sphere with a negative radius",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"].push_back({{"extensions", {{"VKRT_sphere", {{"radius", -1.0}}}}}});
             d["scenes"][0]["nodes"].push_back(1);
             writeJson(file, d);
         },
         "radius"},
        {"sphere with a missing material",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"].push_back({{"extensions", {{"VKRT_sphere", {{"radius", 1.0}, {"material", 3}}}}}});
             d["scenes"][0]["nodes"].push_back(1);
             writeJson(file, d);
         },
         "material"},
        {"sphere under a non-uniform scale",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"].push_back(
                 {{"scale", {1.0, 2.0, 1.0}}, {"extensions", {{"VKRT_sphere", {{"radius", 1.0}}}}}});
             d["scenes"][0]["nodes"].push_back(1);
             writeJson(file, d);
         },
         "uniformly"},
        {"sphere placed beyond single precision",  // its centre, finite in double, became infinite
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"].push_back({{"scale", {1e20, 1e20, 1e20}}, {"children", {2}}});
             d["nodes"].push_back(
                 {{"translation", {1e20, 0.0, 0.0}}, {"extensions", {{"VKRT_sphere", {{"radius", 1e-21}}}}}});
             d["scenes"][0]["nodes"].push_back(1);
             writeJson(file, d);
         },
         "not finite in single precision"},
        {"sphere scaled to nothing within the shutter",
         [](auto&, auto& file) {
             json d = animatedTriangle(0.0f, 1.0f, 2, 1.0f);                 // keys (0, 0, 0) and (1, 1, 1)
             d["animations"][0]["channels"][0]["target"]["path"] = "scale";  // scale 0 at the opening
             d["nodes"][0]["extensions"] = {{"VKRT_sphere", {{"radius", 1.0}}}};
             writeJson(file, d);
         },
         "scales it to nothing within the shutter"},
        {"animation keys out of order",
         [](auto&, auto& file) { writeJson(file, animatedTriangle(1.0f, 0.0f)); }, "increasing"},
        {"animation with fewer values than keys",
         [](auto&, auto& file) { writeJson(file, animatedTriangle(0.0f, 1.0f, 1)); }, "do not match"},
        {"animation of a node that does not exist",
         [](auto&, auto& file) {
             json d = animatedTriangle(0.0f, 1.0f);
             d["animations"][0]["channels"][0]["target"]["node"] = 9;
             writeJson(file, d);
         },
         "node 9"},
        {"shutter that closes before it opens",
         [](auto&, auto& file) {
             json d = animatedTriangle(0.0f, 1.0f);
             d["scenes"][0]["extras"]["shutter"] = {1.0, 0.0};
             writeJson(file, d);
         },
         "shutter"},
        {"node cycle",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"] =
                 json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {2}}}, {{"children", {1}}}});
             writeJson(file, d);
         },
         "cycle"},
        {"node that is its own child",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"][0]["children"] = {0};
             writeJson(file, d);
         },
         "cycle"},
        {"node with two parents",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"] = json::array({{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}});
             d["scenes"][0]["nodes"] = {0, 1};
             writeJson(file, d);
         },
         "two parents"},
        {"mesh index out of range",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"][0]["mesh"] = 5;
             writeJson(file, d);
         },
         "mesh 5"},
        {"missing image",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["images"] = {{{"uri", "no-such-image.png"}}};
             d["textures"] = {{{"source", 0}}};
             d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
             d["meshes"][0]["primitives"][0]["material"] = 0;
             writeJson(file, d);
         },
         "no-such-image.png"},
        {"image that is not one",
         [](auto& folder, auto& file) {
             test::writeText(folder / "garbage.png", "this is text, not a picture");
             json d = validTriangle();
             d["images"] = {{{"uri", "garbage.png"}}};
             d["textures"] = {{{"source", 0}}};
             d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
             d["meshes"][0]["primitives"][0]["material"] = 0;
             writeJson(file, d);
         },
         "image 0 ('garbage.png') could not be decoded: it is not an image vkrt can decode"},
        {"unsupported required extension",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensionsUsed"] = {"KHR_texture_basisu"};
             d["extensionsRequired"] = {"KHR_texture_basisu"};
             writeJson(file, d);
         },
         "requires extension KHR_texture_basisu"},
        {"more materials than the volume stack can name",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["materials"] = json::array();
             for (int i = 0; i < 65535; ++i) d["materials"].push_back(json::object());
             writeJson(file, d);
         },
         "65535 materials"},
        {"Draco-compressed mesh with data that is not Draco data",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensionsUsed"] = {"KHR_draco_mesh_compression"};
             d["extensionsRequired"] = {"KHR_draco_mesh_compression"};
             d["accessors"][1].erase("bufferView");  // the indices live in the compressed data
             d["meshes"][0]["primitives"][0]["extensions"] = {
                 {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
             writeJson(file, d);
         },
         "KHR_draco_mesh_compression: the compressed data does not decode"},
        // Integers that tinygltf keeps as 32-bit ints, given 2^32 more than a valid value: it read the valid
        // one.
        {"sparse count of 2^32 + 1",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][0]["sparse"] = {{"count", (uint64_t{1} << 32) + 1},
                                            {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                            {"values", {{"bufferView", 0}}}};
             writeJson(file, d);
         },
         "accessors[0].sparse.count: expected a number in [1, 2147483647], got 4294967297"},
        {"texture coordinate set 2^32",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["images"] = {{{"uri", "no-such-image.png"}}};
             d["textures"] = {{{"source", 0}}};
             d["materials"] = {{{"emissiveTexture", {{"index", 0}, {"texCoord", uint64_t{1} << 32}}}}};
             writeJson(file, d);
         },
         "materials[0].emissiveTexture.texCoord: expected a number in [0, 2147483647], got 4294967296"},
        // Compression extensions' properties of the wrong type or naming nothing: tinygltf's messages, or the
        // decoder's, named another property or the wrong problem.
        {"Draco buffer view that does not exist",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][1].erase("bufferView");
             d["meshes"][0]["primitives"][0]["extensions"] = {
                 {"KHR_draco_mesh_compression", {{"bufferView", 99}, {"attributes", {{"POSITION", 0}}}}}};
             writeJson(file, d);
         },
         "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression.bufferView: buffer view 99 does not "
         "exist"},
        {"Draco extension naming no attributes",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][1].erase("bufferView");
             d["meshes"][0]["primitives"][0]["extensions"] = {
                 {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", json::object()}}}};
             writeJson(file, d);
         },
         "KHR_draco_mesh_compression: the compressed data does not decode"},
        {"meshopt extension that is not an object",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["bufferViews"][0]["extensions"] = {{"EXT_meshopt_compression", 5}};
             writeJson(file, d);
         },
         "bufferViews[0].extensions.EXT_meshopt_compression: expected an object"},
        {"meshopt mode as a number",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["bufferViews"][0]["extensions"] = {
                 {"EXT_meshopt_compression",
                  {{"buffer", 0}, {"byteLength", 36}, {"byteStride", 12}, {"count", 3}, {"mode", 1}}}};
             writeJson(file, d);
         },
         "bufferViews[0].extensions.EXT_meshopt_compression.mode: expected a string"},
        // Properties of the wrong JSON type or out of range, which tinygltf alone would skip: each is named
        // by its JSON path.
        {"primitives as an object",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["meshes"][0]["primitives"] = d["meshes"][0]["primitives"][0];
             writeJson(file, d);
         },
         "meshes[0].primitives: expected an array"},
        {"pbrMetallicRoughness as an array",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["materials"] = {{{"pbrMetallicRoughness", {0.5, 0.5}}}};
             writeJson(file, d);
         },
         "materials[0].pbrMetallicRoughness: expected an object"},
        {"texture index -1",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", -1}}}}}}};
             writeJson(file, d);
         },
         "materials[0].pbrMetallicRoughness.baseColorTexture.index: expected a number >= 0, got -1"},
        {"texture transform as text",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["images"] = {{{"uri", "no-such-image.png"}}};
             d["textures"] = {{{"source", 0}}};
             d["materials"] = {{{"emissiveTexture",
                                 {{"index", 0}, {"extensions", {{"KHR_texture_transform", "text"}}}}}}};
             writeJson(file, d);
         },
         "materials[0].emissiveTexture.extensions.KHR_texture_transform: expected an object"},
        {"texture whose image does not exist",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["textures"] = {{{"source", 2}}};
             d["materials"] = {{{"normalTexture", {{"index", 0}}}}};
             writeJson(file, d);
         },
         "materials[0].normalTexture.index (its texture's source): image 2 does not exist"},
        {"base colour above one",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.5, 1.0, 1.0}}}}}};
             writeJson(file, d);
         },
         "materials[0].pbrMetallicRoughness.baseColorFactor[1]: expected a number in [0, 1], got 1.5"},
        {"roughness as text",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["materials"] = {{{"pbrMetallicRoughness", {{"roughnessFactor", "0.5"}}}}};
             writeJson(file, d);
         },
         "materials[0].pbrMetallicRoughness.roughnessFactor: expected a number"},
        {"malformed supported extension",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensionsUsed"] = {"KHR_materials_ior"};
             d["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", 0.5}}}}}}};
             writeJson(file, d);
         },
         "materials[0].extensions.KHR_materials_ior.ior: expected 0 or a number >= 1, got 0.5"},
        {"light whose colour times intensity overflows single precision",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensionsUsed"] = {"KHR_lights_punctual"};
             d["extensions"] = {
                 {"KHR_lights_punctual",
                  {{"lights", {{{"type", "point"}, {"color", {1e30, 1.0, 1.0}}, {"intensity", 1e30}}}}}}};
             d["nodes"][0]["extensions"] = {{"KHR_lights_punctual", {{"light", 0}}}};
             writeJson(file, d);
         },
         "light 0: color times intensity is beyond single precision (3.4e38)"},
        {"emission whose factor times strength overflows single precision",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensionsUsed"] = {"KHR_materials_emissive_strength"};
             d["materials"] = {
                 {{"emissiveFactor", {0.0, 1e20, 0.0}},
                  {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e20}}}}}}};
             writeJson(file, d);
         },
         "material 0: emissiveFactor times emissiveStrength is beyond single precision (3.4e38)"},
        {"light index that names nothing",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}}}}}}};
             d["nodes"][0]["extensions"] = {{"KHR_lights_punctual", {{"light", 1}}}};
             writeJson(file, d);
         },
         "nodes[0].extensions.KHR_lights_punctual.light: light 1 does not exist (the file has 1)"},
        {"spot light without its cone",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "spot"}}}}}}};
             writeJson(file, d);
         },
         "extensions.KHR_lights_punctual.lights[0].spot: missing, and required"},
        {"accessor of an unknown type",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["accessors"][0]["type"] = "VEC5";
             writeJson(file, d);
         },
         "accessors[0].type: expected one of"},
        {"fractional index",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["meshes"][0]["primitives"][0]["indices"] = 1.5;
             writeJson(file, d);
         },
         "meshes[0].primitives[0].indices: expected an integer"},
        {"node rotation as a string",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"][0]["rotation"] = "identity";
             writeJson(file, d);
         },
         "nodes[0].rotation: expected an array of 4 numbers"},
        {"scene that does not exist",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["scene"] = 1;
             writeJson(file, d);
         },
         "scene: scene 1 does not exist (the file has 1)"},
        {"camera whose far plane is not beyond its near plane",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["cameras"] = json::array();
             d["cameras"].push_back(
                 {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 1.0}, {"zfar", 0.5}}}});
             writeJson(file, d);
         },
         "cameras[0].perspective.zfar: expected more than znear"},
        {"camera without its projection",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["cameras"] = {{{"type", "perspective"}}};
             writeJson(file, d);
         },
         "cameras[0].perspective: missing, and required"},
        {"camera with both projections",  // glTF 2.0: each MUST NOT be defined when the other is
         [](auto&, auto& file) {
             json d = validTriangle();
             d["cameras"] = {
                 {{"type", "perspective"},
                  {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}},
                  {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}}};
             writeJson(file, d);
         },
         "cameras[0].orthographic: must not be defined when type is \"perspective\""},
        {"GLB whose JSON has the wrong types",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"][0]["children"] = {"one"};
             const std::string text = d.dump();
             const std::string padded = text + std::string((4 - text.size() % 4) % 4, ' ');
             auto word = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
             file.replace_extension(".glb");
             test::writeText(file, "glTF" + word(2) + word(static_cast<uint32_t>(20 + padded.size())) +
                                       word(static_cast<uint32_t>(padded.size())) + "JSON" + padded);
         },
         "nodes[0].children[0]: expected an integer"},
        {"truncated GLB",
         [](auto&, auto& file) {
             file.replace_extension(".glb");
             test::writeText(file, std::string("glTF\x02\x00\x00\x00\xff\x00\x00\x00", 12));
         },
         ""},
        {"not glTF at all", [](auto&, auto& file) { test::writeText(file, "P6\n1 1\n255\n\x01\x02\x03"); },
         ""},
        // tinygltf reads nested values by recursion: 20,000 levels in extras overflowed its stack (SIGSEGV).
        {"JSON nested 20,000 levels deep",
         [](auto&, auto& file) {
             std::string text = validTriangle().dump();
             text.pop_back();  // the closing brace
             test::writeText(file,
                             text + ",\"extras\":" + std::string(20000, '[') + std::string(20000, ']') + "}");
         },
         "JSON nested more than 512 levels deep"},
        {"glTF 1.0",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["asset"]["version"] = "1.0";
             writeJson(file, d);
         },
         "asset.version: glTF 1.0 is not glTF 2.x"},
        {"version of 100,000 digits",  // std::regex_match recursed once a character, and overflowed the stack
         [](auto&, auto& file) {
             json d = validTriangle();
             d["asset"]["version"] = "2." + std::string(100000, '0') + "\nx";
             writeJson(file, d);
         },
         "asset.version: expected <major>.<minor>, got \"2.000"},
        {"newer minor version required",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["asset"] = {{"version", "2.1"}, {"minVersion", "2.1"}};
             writeJson(file, d);
         },
         "asset.minVersion: requires glTF \"2.1\""},
        {"number beyond single precision",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["nodes"][0]["translation"] = {1e39, 0.0, 0.0};
             writeJson(file, d);
         },
         "nodes[0].translation[0]: expected a number within single precision's range"},
        {"buffer that is a directory",
         [](auto&, auto& file) {
             json d = validTriangle();
             d["buffers"][0]["uri"] = ".";
             writeJson(file, d);
         },
         "not a regular file"},
        {"GLB of version 1",
         [](auto&, auto& file) {
             file.replace_extension(".glb");
             std::string text = validTriangle().dump();
             text.resize((text.size() + 3) / 4 * 4, ' ');
             const auto word = [](size_t v) {
                 return std::string{static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                                    static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
             };
             test::writeText(file,
                             "glTF" + word(1) + word(20 + text.size()) + word(text.size()) + "JSON" + text);
         },
         "GLB version 1; vkrt reads GLB version 2"},
    };
}

TEST(BadInput, LoaderThrowsOneLineSceneError) {
    const auto folder = test::temporaryFolder();
    for (const BadCase& c : badCases()) {
        SCOPED_TRACE(c.name);
        std::filesystem::path file = fileFor(folder, c.name);
        c.make(folder, file);
        try {
            loadGltf(file.string());
            ADD_FAILURE() << "loaded without error";
        } catch (const SceneError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            EXPECT_NE(message.find(file.string()), std::string::npos) << "names the file: " << message;
            EXPECT_NE(message.find(c.expected), std::string::npos) << message;
        }
    }
}

TEST(BadInput, CommandExitsWithCodeTwoAndWritesNothing) {
    const auto folder = test::temporaryFolder();
    for (const BadCase& c : badCases()) {
        SCOPED_TRACE(c.name);
        std::filesystem::path file = fileFor(folder, c.name);
        c.make(folder, file);
        const auto output = folder / "out.png";
        const auto stats = folder / "stats.json";
        const test::CommandResult result =
            test::runVkrt("--scene '" + file.string() + "' --out '" + output.string() + "' --stats '" +
                          stats.string() + "' --width 8 --height 8");
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_NE(result.output.find("vkrt: error: "), std::string::npos) << result.output;
        EXPECT_FALSE(std::filesystem::exists(output));
        EXPECT_FALSE(std::filesystem::exists(stats));
    }
    // Nothing half-written is left behind either.
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    }
}

TEST(BadInput, UnusableEnvironmentExitsTwoAndWritesNothing) {
    const auto folder = test::temporaryFolder();
    // Maps vkrt cannot use: missing, of another format, not really HDR, and with texels that are not
    // radiance (written as EXR, which holds any float).
    test::writeText(folder / "text.hdr", "#?RADIANCE\nnot really\n");
    test::writeText(folder / "picture.hdr", std::string("\x89PNG\r\n\x1a\n", 8));
    // Run-length encoded scanlines of 8 texels that end early, or hold a run of length 0: stb_image read a
    // count of 0 in both and looped forever.
    const std::string rle =
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n" + std::string("\x02\x02\x00\x08", 4);
    test::writeText(folder / "truncated.hdr", rle + "\x88\x40");
    test::writeText(folder / "zero-run.hdr", rle + std::string("\x88\x40\x00", 3));
    Image negative(2, 1), notFinite(2, 1);
    negative.at(1, 0) = glm::vec3(0.5f, -1.0f, 0.5f);
    notFinite.at(0, 0) = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    writeImage(negative, (folder / "negative.exr").string());
    writeImage(notFinite, (folder / "nan.exr").string());
    // A size of -5 rows (stb_image takes it as such: the texel count wrapped around to 1.8e19), and an EXR
    // cut short (tinyexr's message ended in a newline: a second, empty line).
    test::writeText(folder / "negative-size.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y -5 +X 3\n" +
                                                      std::string("\x80\x80\x80\x81", 4));
    Image whole(64, 64);
    writeImage(whole, (folder / "whole.exr").string());
    const std::string exr = test::readText(folder / "whole.exr");
    test::writeText(folder / "cut.exr", exr.substr(0, exr.size() - 100));
    Image bright(2, 1);
    bright.at(0, 0) = glm::vec3(1.0f);
    bright.at(1, 0) = glm::vec3(5.0f);  // times a strength of 1e38, beyond float's range
    writeImage(bright, (folder / "bright.exr").string());
    const std::string scene = "'" + (test::sourceDir() / "scenes/environment.gltf").string() + "'";
    struct Case {
        std::string options;
        std::string expected;
    };
    for (const Case& c :
         {Case{"--environment '" + (folder / "missing.hdr").string() + "'", "missing.hdr: cannot open"},
          Case{"--environment '" + (folder / "sky.png").string() + "'", "use .hdr or .exr"},
          Case{"--environment '" + (folder / "text.hdr").string() + "'", "text.hdr: cannot read"},
          Case{"--environment '" + (folder / "picture.hdr").string() + "'", "not a Radiance HDR"},
          Case{"--environment '" + (folder / "negative.exr").string() + "'",
               "texel (1, 0) of the environment map is negative"},
          Case{"--environment '" + (folder / "nan.exr").string() + "'", "is not finite"},
          Case{"--environment '" + (folder / "truncated.hdr").string() + "'",
               "truncated.hdr: cannot read Radiance HDR: truncated or corrupt run-length data"},
          Case{"--environment '" + (folder / "zero-run.hdr").string() + "'",
               "zero-run.hdr: cannot read Radiance HDR: truncated or corrupt run-length data"},
          Case{"--environment '" + (folder / "negative-size.hdr").string() + "'",
               "negative-size.hdr: its resolution line gives a size of 3 x -5"},
          Case{"--environment '" + (folder / "cut.exr").string() + "'", "cut.exr: cannot read EXR: "},
          Case{"--environment-strength -1", "must not be negative"},
          Case{"--environment-strength 1e39", "beyond single precision's range"},
          Case{"--environment '" + (folder / "bright.exr").string() + "' --environment-strength 1e38",
               "texel (1, 0) of the environment map times the strength 1e+38 is beyond single precision's "
               "range"},
          Case{"--environment-rotation inf", "is not finite"}}) {
        SCOPED_TRACE(c.options);
        const auto output = folder / "out.png";
        const test::CommandResult result = test::runVkrt("--scene " + scene + " " + c.options + " --out '" +
                                                         output.string() + "' --width 8");
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_EQ(result.output.rfind("vkrt: error: ", 0), 0u) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_NE(result.output.find(c.expected), std::string::npos) << result.output;
        EXPECT_FALSE(std::filesystem::exists(output));
    }
}

// Options out of their range, files a run would write twice and references that are not radiance: exit 2 with
// one line naming the option, and nothing written.
TEST(BadInput, UnusableOptionsAndReferencesExitTwoAndWriteNothing) {
    const auto folder = test::temporaryFolder();
    const std::string scene = "'" + (test::sourceDir() / "scenes/cornell.gltf").string() + "'";
    test::writeText(folder / "huge.pfm", "PF\n100000 100000\n-1.0\n");  // its pixels would need 120 GB
    test::writeText(folder / "vast.pfm", "PF\n1000000000 1000000000\n-1.0\n");  // 12e18 bytes: past 64 bits
    Image notFinite(8, 8);
    notFinite.at(3, 2) = glm::vec3(std::numeric_limits<float>::infinity());
    writeImage(notFinite, (folder / "inf.pfm").string());
    const std::string out = "'" + (folder / "out.pfm").string() + "'";
    struct Case {
        std::string options;
        std::string expected;
    };
    for (const Case& c :
         {Case{"--background -1", "--background: '-1' is a radiance and must not be negative"},
          Case{"--ambient 0,-0.5,0 --integrator whitted",
               "--ambient: '0,-0.5,0' is a radiance and must not be negative"},
          Case{"--background 1e39", "--background: '1e39' is not one finite value"},
          Case{"--animation walk", "--animation walk: no such animation (the file has none)"},
          Case{"--aperture 1e39", "--aperture: '1e39' is beyond single precision's range"},
          Case{"--stats " + out, "--out and --stats name the same file"},
          Case{"--report-every-ms 5", "--report-every-ms needs --report, where its checkpoints are written"},
          Case{"--reference '" + (folder / "huge.pfm").string() + "' --report-every-ms 5",
               "--report-every-ms needs --report, where its checkpoints are written"},
          Case{"--report '" + (folder / "r.json").string() + "' --stats '" + (folder / "./r.json").string() +
                   "'",
               "--stats and --report name the same file"},
          Case{"--report '" + (folder / "r.json").string() + "' --reference '" +
                   (folder / "huge.pfm").string() + "'",
               "--reference: " + (folder / "huge.pfm").string() + ": file is truncated"},
          Case{"--report '" + (folder / "r.json").string() + "' --reference '" +
                   (folder / "vast.pfm").string() + "'",
               "--reference: " + (folder / "vast.pfm").string() + ": file is truncated"},
          Case{"--report '" + (folder / "r.json").string() + "' --reference '" +
                   (folder / "inf.pfm").string() + "'",
               "inf.pfm: pixel (3, 2) is not finite"},
          Case{"--report '" + (folder / "r.json").string() + "' --reference '" +
                   (folder / "missing.exr").string() + "'",
               "--reference: " + (folder / "missing.exr").string() + ": cannot open: no such file"},
          Case{"--report '" + (folder / "r.json").string() + "' --reference '" +
                   (test::sourceDir() / "scenes/sky.hdr").string() + "'",
               "sky.hdr: not .exr or .pfm, the formats of linear radiance vkrt reads"}}) {
        SCOPED_TRACE(c.options);
        const test::CommandResult result = test::runVkrt(
            "--scene " + scene + " --device cpu --width 8 --height 8 --spp 1 --out " + out + " " + c.options);
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_EQ(result.output.rfind("vkrt: error: ", 0), 0u) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_NE(result.output.find(c.expected), std::string::npos) << result.output;
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 3) << "wrote nothing";
}

// Outputs that name one file in different words are refused before the file exists too: a relative path and
// the same one through `./` or in full (weakly_canonical left the first relative and made the second
// absolute, so the stats were written over the image, exit 0), and a link to a file not there yet.
TEST(BadInput, OutputsNamingOneFileInOtherWordsAreRefused) {
    const auto folder = test::temporaryFolder();
    std::filesystem::create_symlink("s.png", folder / "link.json");
    const std::string scene = "'" + (test::sourceDir() / "scenes/cornell.gltf").string() + "'";
    for (const std::string& outputs :
         {std::string("--out img.png --stats ./img.png"),
          "--out img.png --stats '" + (folder / "img.png").string() + "'",
          std::string("--out img.png --stats sub/../img.png"), std::string("--out s.png --stats link.json"),
          std::string("--out r.png --stats s.json --report ./s.json")}) {
        SCOPED_TRACE(outputs);
        std::filesystem::create_directory(folder / "sub");
        const test::CommandResult result =
            test::runCommand("cd '" + folder.string() + "' && '" + std::string(VKRT_BINARY) + "' --scene " +
                             scene + " --device cpu --width 8 --spp 1 " + outputs);
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_NE(result.output.find("name the same file"), std::string::npos) << result.output;
        EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 2) << "wrote nothing";
    }
}

// Nor are the files a scene refers to written over: its image and stats written over the scene's texture and
// buffer (exit 0) broke every later render of it.
TEST(BadInput, OutputsOverTheScenesOwnFilesAreRefused) {
    const auto folder = test::temporaryFolder();
    const std::vector<uint8_t> bytes = triangleBytes();
    test::writeText(folder / "triangle.bin", std::string(bytes.begin(), bytes.end()));
    writeImage(Image(2, 2), (folder / "texture.png").string());
    json d = validTriangle();
    d["buffers"][0]["uri"] = "triangle.bin";
    d["images"] = {{{"uri", "texture.png"}}};
    d["textures"] = {{{"source", 0}}};
    writeJson(folder / "scene.gltf", d);
    for (const auto& [outputs, expected] :
         {std::pair{std::string("--out texture.png"),
                    "--out would write over a file the scene reads: texture.png"},
          {std::string("--out x.png --stats ./triangle.bin"),
           "--stats would write over a file the scene reads: ./triangle.bin"}}) {
        SCOPED_TRACE(outputs);
        const test::CommandResult result =
            test::runCommand("cd '" + folder.string() + "' && '" + std::string(VKRT_BINARY) +
                             "' --scene scene.gltf --device cpu --width 8 --spp 1 " + outputs);
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
        EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 3) << "wrote nothing";
    }
    EXPECT_EQ(test::readText(folder / "triangle.bin"), std::string(bytes.begin(), bytes.end()));
}

// A file name of 250 bytes is allowed (file systems take 255): the temporary name it is written under first
// keeps within that too, where a suffix added to the whole name made the write fail after the render.
TEST(BadInput, LongOutputNamesAreWritten) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / (std::string(246, 'a') + ".png");
    const auto stats = folder / (std::string(245, 'b') + ".json");
    const test::CommandResult result =
        test::runVkrt("--scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() +
                      "' --device cpu --width 8 --height 8 --spp 1 --quiet --out '" + image.string() +
                      "' --stats '" + stats.string() + "'");
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_TRUE(std::filesystem::exists(image));
    EXPECT_TRUE(std::filesystem::exists(stats));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 2) << "no temporary file left";
}

// Paths are checked before anything is loaded or rendered: each case asks for a render that would take hours
// (16384 x 16384 at 4096 spp on the CPU), so a check made only after rendering would time the test out.
TEST(BadInput, PathsAreCheckedBeforeAnythingIsRendered) {
    const auto folder = test::temporaryFolder();
    const std::string scene = "'" + (test::sourceDir() / "scenes/cornell.gltf").string() + "'";
    const std::string huge = " --device cpu --width 16384 --height 16384 --spp 4096";
    std::filesystem::create_directory(folder / "folder.png");
    struct Case {
        std::string options;
        std::string expected;
    };
    for (const Case& c :
         {Case{"--scene '" + (test::sourceDir() / "scenes").string() + "' --out '" +
                   (folder / "a.png").string() + "'",
               "--scene: " + (test::sourceDir() / "scenes").string() + ": is a directory"},
          Case{"--scene " + scene + " --out '" + (folder / "no/such/dir/x.png").string() + "'",
               "--out: " + (folder / "no/such/dir/x.png").string() + ": folder " +
                   (folder / "no/such/dir").string() + " does not exist"},
          Case{"--scene " + scene + " --out '" + (folder / "folder.png").string() + "'",
               "--out: " + (folder / "folder.png").string() + ": is a directory"},
          Case{"--scene " + scene + " --out '" + (folder / "b.png").string() + "' --stats '" +
                   (folder / "missing/s.json").string() + "'",
               "--stats: " + (folder / "missing/s.json").string() + ": folder"},
          Case{"--scene " + scene + " --out '" + (folder / "c.png").string() + "' --report '" +
                   (folder / "missing/r.csv").string() + "'",
               "--report: " + (folder / "missing/r.csv").string() + ": folder"},
          // A name longer than the file system holds failed only at the rename, after the render; a device as
          // the scene (/dev/zero) was read until the memory ran out.
          Case{"--scene " + scene + " --out '" + (folder / (std::string(252, 'n') + ".png")).string() + "'",
               ": the file name has 256 bytes; the folder's file system takes at most"},
          Case{"--scene " + scene + " --out '" + (folder / "d.png").string() + "' --stats '" +
                   (folder / (std::string(300, 's') + ".json")).string() + "'",
               "--stats: "},
          Case{"--scene /dev/zero --out '" + (folder / "e.png").string() + "'",
               "--scene: /dev/zero: is a device, not a file"}}) {
        SCOPED_TRACE(c.options);
        const test::CommandResult result = test::runVkrt(c.options + huge);
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_EQ(result.output.rfind("vkrt: error: ", 0), 0u) << result.output;
        EXPECT_NE(result.output.find(c.expected), std::string::npos) << result.output;
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1) << "wrote nothing";
    // The loader itself says so too, for callers other than the command.
    try {
        loadGltf((test::sourceDir() / "scenes").string());
        ADD_FAILURE() << "loaded a directory";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
    }
}

// A scene given through a named pipe (as a shell's `<(...)` gives it) loads: the scene file is read once. The
// path check opened it and closed it again, dropping what the writer had sent, and the loader read the file
// four times; vkrt waited for data that never came. An empty file says so.
TEST(BadInput, SceneThroughANamedPipeLoads) {
    const auto folder = test::temporaryFolder();
    const std::string pipe = (folder / "scene.glb").string(), image = (folder / "x.png").string();
    for (const char* scene : {"scenes/cornell.gltf", "scenes/cornell-meshopt.glb"}) {
        SCOPED_TRACE(scene);
        std::filesystem::remove(pipe);
        const test::CommandResult run = test::runCommand(
            "mkfifo '" + pipe + "' && { { timeout 60 cat '" + (test::sourceDir() / scene).string() + "' > '" +
            pipe + "'; } >/dev/null 2>&1 & timeout 60 '" + std::string(VKRT_BINARY) + "' --scene '" + pipe +
            "' --device cpu --width 8 --height 8 --spp 1 --quiet --out '" + image + "'; echo \"exit=$?\"; }");
        EXPECT_NE(run.output.find("exit=0"), std::string::npos) << run.output;
        EXPECT_TRUE(std::filesystem::exists(image));
        std::filesystem::remove(image);
    }
    test::writeText(folder / "empty.gltf", "");
    const test::CommandResult empty =
        test::runVkrt("--scene '" + (folder / "empty.gltf").string() + "' --out '" + image + "'");
    EXPECT_EQ(empty.exitCode, 2) << empty.output;
    EXPECT_NE(empty.output.find("empty.gltf: the file is empty"), std::string::npos) << empty.output;
}

// A texture's image holding Radiance HDR data whose run-length encoded scanline is cut short or holds a run
// of length 0: stb_image, through which tinygltf decoded it, looped forever on both. glTF textures are PNG
// or JPEG (and WebP or KTX2 by extension), so HDR data is refused without being decoded. The command runs
// under a time limit, so that a hang fails the test instead of stopping the suite.
TEST(BadInput, HdrTextureDataIsRefusedWithoutDecoding) {
    const auto folder = test::temporaryFolder();
    const std::string rle =
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n" + std::string("\x02\x02\x00\x08", 4);
    const std::string cutShort = rle, zeroRun = rle + std::string(41, '\0');
    for (const std::string& hdr : {cutShort, zeroRun}) {
        json d = validTriangle();
        d["accessors"].push_back(
            {{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
        d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
        d["meshes"][0]["primitives"][0]["material"] = 0;
        d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
        d["textures"] = {{{"source", 0}}};
        d["images"] = {{{"uri", "data:image/vnd.radiance;base64," +
                                    base64(std::vector<uint8_t>(hdr.begin(), hdr.end()))}}};
        const auto file = folder / "hdr-texture.gltf";
        writeJson(file, d);
        const auto output = folder / "out.png";
        const test::CommandResult result =
            test::runCommand("timeout 60 '" + std::string(VKRT_BINARY) + "' --scene '" + file.string() +
                             "' --device cpu --width 8 --height 8 --spp 1 --out '" + output.string() + "'");
        EXPECT_EQ(result.exitCode, 2) << result.output;
        EXPECT_NE(result.output.find(file.string() + ": "), std::string::npos) << result.output;
        EXPECT_NE(result.output.find("image 0 could not be decoded: it holds Radiance HDR data"),
                  std::string::npos)
            << result.output;
        EXPECT_FALSE(std::filesystem::exists(output));
    }
}

// Inputs found by fuzzing (tools/fuzz_loader.sh) or made to break the loader: each must load or fail with one
// SceneError, never crash, run out of memory or throw anything else.
TEST(BadInput, FuzzRegressionsLoadOrFailCleanly) {
    size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::sourceDir() / "tests/fuzz/regressions")) {
        SCOPED_TRACE(entry.path().string());
        ++files;
        try {
            loadGltf(entry.path().string());
        } catch (const SceneError& e) {
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    }
    EXPECT_GE(files, 3u);
}

// A node hierarchy 100,000 levels deep is walked with the loader's own stacks, not the call stack.
TEST(BadInput, DeepHierarchyLoads) {
    json d = validTriangle();
    d["nodes"] = json::array({{{"children", {1}}}});
    for (int i = 1; i < 100000; ++i) d["nodes"].push_back({{"children", {i + 1}}});
    d["nodes"].push_back({{"mesh", 0}, {"translation", {0.0, 0.0, 1.0}}});
    const auto file = test::temporaryFolder() / "deep.gltf";
    writeJson(file, d);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 1u);
    EXPECT_EQ(scene.triangles[0].v0.z + scene.origin.z, 1.0);
}

TEST(BadInput, ValidAnimationLoadsAndMoves) {
    const auto file = test::temporaryFolder() / "animated.gltf";
    writeJson(file, animatedTriangle(0.0f, 1.0f));
    const Scene scene = loadGltf(file.string());
    ASSERT_TRUE(scene.moving());
    EXPECT_EQ(scene.motionSegments, 1);  // linear translation: one exact segment
    EXPECT_NEAR(scene.trianglePose(0, 1).v0.x - scene.triangles[0].v0.x, 1.0f, 1e-6f);
}

// A shutter that closes at the double 0.1, just below the last key, 0.1f, to which it rounds in float: the
// pose there is the last key's. The key search compared in float, found no key after the time and read
// beyond the times and values (AddressSanitizer in tools/sanitize_check.sh).
TEST(BadInput, ShutterJustBelowTheLastKeyTakesItsPose) {
    const auto file = test::temporaryFolder() / "animated.gltf";
    json d = animatedTriangle(0.0f, 0.1f);
    d["scenes"][0]["extras"]["shutter"] = {0.0, 0.1};
    ASSERT_LT(0.1, static_cast<double>(0.1f));
    writeJson(file, d);
    const Scene scene = loadGltf(file.string());
    ASSERT_TRUE(scene.moving());
    EXPECT_NEAR(scene.trianglePose(0, 1).v0.x - scene.triangles[0].v0.x, 1.0f, 1e-6f);
}

// A sphere whose node is scaled to nothing is hidden, as glTF hides such a node: skipped with a warning, as a
// mesh's vanished triangles are (it once failed the file).
TEST(BadInput, SphereScaledToNothingIsSkipped) {
    const auto file = test::temporaryFolder() / "hidden.gltf";
    json d = validTriangle();
    d["nodes"].push_back({{"scale", {0.0, 0.0, 0.0}}, {"extensions", {{"VKRT_sphere", {{"radius", 1.0}}}}}});
    d["scenes"][0]["nodes"].push_back(1);
    writeJson(file, d);
    const Scene scene = loadGltf(file.string());
    EXPECT_TRUE(scene.spheres.empty());
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("VKRT_sphere: the node scales it to nothing; it is skipped"),
              std::string::npos)
        << scene.warnings[0];
}

// An error quotes no more than a line's worth of what the file holds: a buffer whose data URI tinygltf could
// not decode (its byteLength one more than its bytes) was quoted whole, an error line of 4 MB.
TEST(BadInput, ErrorsQuoteALinesWorthOfTheFile) {
    const auto folder = test::temporaryFolder();
    const std::vector<uint8_t> bytes(3000000, 0);
    json d = validTriangle();
    d["buffers"] = {
        {{"byteLength", bytes.size() + 1}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}};
    writeJson(folder / "long.gltf", d);
    const test::CommandResult result = test::runVkrt("--scene '" + (folder / "long.gltf").string() +
                                                     "' --out '" + (folder / "x.png").string() + "'");
    EXPECT_EQ(result.exitCode, 2);
    EXPECT_LT(result.output.size(), 1000u) << result.output.substr(0, 1000);
    EXPECT_NE(result.output.find("long.gltf: "), std::string::npos) << result.output.substr(0, 1000);
}

TEST(BadInput, IndicesAndNormalScalesBeyondSinglePrecisionsReachAreClamped) {
    // An index of refraction above 1e6 is 1e6 (its square overflowed the GPU's single precision
    // beyond 1.8e19: NaN samples, the image 40% dark), and a normal texture's scale at most 1e6 either way
    // (its mapped normal's length overflowed beyond 1.8e19, and the GPU ignored the map); both devices read
    // the clamped values.
    const auto folder = test::temporaryFolder();
    json d = validTriangle();
    d["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_clearcoat"};
    d["images"] = {
        {{"uri",
          "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAE"
          "hQGAhKmMIQAAAABJRU5ErkJggg=="}}};
    d["textures"] = {{{"source", 0}}};
    d["materials"] = {
        {{"normalTexture", {{"index", 0}, {"scale", 1e30}}},
         {"extensions",
          {{"KHR_materials_ior", {{"ior", 1e20}}},
           {"KHR_materials_clearcoat",
            {{"clearcoatFactor", 1.0}, {"clearcoatNormalTexture", {{"index", 0}, {"scale", -1e25}}}}}}}}};
    writeJson(folder / "extreme.gltf", d);
    const Scene scene = loadGltf((folder / "extreme.gltf").string());
    ASSERT_GE(scene.materials.size(), 1u);  // and the default material, for primitives without one
    const Material& material = scene.materials[0];
    EXPECT_EQ(material.clearcoat, 1.0f);
    EXPECT_EQ(material.ior, 1e6f);
    EXPECT_EQ(material.normalScale, 1e6f);
    EXPECT_EQ(material.clearcoatNormalScale, -1e6f);
}

TEST(BadInput, ValidTriangleLoads) {
    // The generator above makes valid files: each bad case differs from this by its one defect.
    const auto folder = test::temporaryFolder();
    writeJson(folder / "valid.gltf", validTriangle());
    const Scene scene = loadGltf((folder / "valid.gltf").string());
    EXPECT_EQ(scene.triangles.size(), 1u);
    // Properties and extensions vkrt does not know are allowed, whatever their type.
    json unknown = validTriangle();
    unknown["nodes"][0]["futureProperty"] = "text";
    unknown["meshes"][0]["primitives"][0]["extensions"] = {{"EXT_someday", {1, 2, 3}}};
    unknown["asset"]["generator"] = "a test";
    unknown["extras"] = 5;
    writeJson(folder / "unknown.gltf", unknown);
    EXPECT_EQ(loadGltf((folder / "unknown.gltf").string()).triangles.size(), 1u);
}

}  // namespace
}  // namespace vkrt
