// The vkrt command: help, exit codes, outputs and the stats JSON.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/progress_bar.h"
#include "gpu/gpu_scene.h"
#include "image/image_io.h"
#include "support/gltf_document.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

std::string quoted(const std::filesystem::path& path) {
    std::string text = "'";
    text += path.string();
    text += "'";
    return text;
}

const std::string kCornell = quoted(test::sourceDir() / "scenes/cornell.gltf");

TEST(Cli, HelpListsTheOptionsAndExitsZero) {
    const auto result = test::runVkrt("--help");
    EXPECT_EQ(result.exitCode, 0);
    for (const char* option :
         {"--scene", "--out", "--width", "--height", "--spp", "--integrator", "--max-depth", "--device",
          "--seed", "--camera", "--stats", "--shader-features"}) {
        EXPECT_NE(result.output.find(option), std::string::npos) << option;
    }
    // Help that cannot be written is a failure (it exited 0 with its output lost).
    EXPECT_EQ(test::runCommand("'" + std::string(VKRT_BINARY) + "' --help > /dev/full").exitCode, 1);
}

TEST(Cli, BadUsageExitsTwoWithOneLine) {
    for (const char* arguments :
         {"", "--scene", "--bogus", "--scene x.gltf --width -3", "--scene x.gltf --spp many",
          "--scene x.gltf --out image.bmp", "--scene x.gltf --device tpu", "--scene x.gltf --shutter 1 0",
          "--scene x.gltf --shutter 0", "--scene x.gltf --integrator bdpt", "--scene x.gltf --max-depth 1025",
          "--scene x.gltf --shader-features some"}) {
        const auto result = test::runVkrt(arguments);
        EXPECT_EQ(result.exitCode, 2) << arguments << ": " << result.output;
        EXPECT_EQ(result.output.rfind("vkrt: error: ", 0), 0u) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    }
}

// Mistakes in a command whose scene is fine: each is refused in one line naming it (exit 2), and nothing is
// written: an empty file name (an empty --reference once rendered its own reference at 16 times the samples),
// a colour with a trailing comma, and an output that would write over an input (--stats over the scene
// replaced it).
TEST(Cli, MistakenValuesAreRefusedBeforeAnythingIsWritten) {
    const auto folder = test::temporaryFolder();
    const std::filesystem::path scene = folder / "scene.gltf";
    std::filesystem::copy_file(test::sourceDir() / "scenes/cornell.gltf", scene);
    const std::string base =
        "--scene " + quoted(scene) + " --device cpu --width 8 --spp 1 --out " + quoted(folder / "x.pfm");
    const std::pair<std::string, const char*> cases[] = {
        {"--stats ''", "--stats needs a file name"},
        {"--reference '' --report " + quoted(folder / "r.json"), "--reference needs a file name"},
        {"--environment ''", "--environment needs a file name"},
        {"--background 1,2,3,", "--background"},
        {"--ambient 1,", "--ambient"},
        {"--stats " + quoted(scene), "--stats would write over --scene"},
    };
    for (const auto& [arguments, message] : cases) {
        const auto result = test::runVkrt(base + " " + arguments);
        EXPECT_EQ(result.exitCode, 2) << arguments << ": " << result.output;
        EXPECT_NE(result.output.find(message), std::string::npos) << arguments << ": " << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_FALSE(std::filesystem::exists(folder / "x.pfm")) << arguments;
    }
    EXPECT_EQ(test::readText(scene), test::readText(test::sourceDir() / "scenes/cornell.gltf"));
}

// Whole numbers are decimal whatever leading zeros they have (CLI11 alone read "010" as octal 8 and refused
// "08").
TEST(Cli, WholeNumbersAreDecimal) {
    const auto folder = test::temporaryFolder();
    const auto result = test::runVkrt(
        "--scene " + kCornell + " --device cpu --width 016 --height 08 --spp 010 " +
        "--seed 0100 --quiet --out " + quoted(folder / "x.pfm") + " --stats " + quoted(folder / "x.json"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    std::ifstream file(folder / "x.json");
    const nlohmann::json stats = nlohmann::json::parse(file);
    EXPECT_EQ(stats["width"], 16);
    EXPECT_EQ(stats["height"], 8);
    EXPECT_EQ(stats["spp"], 10);
    EXPECT_EQ(stats["seed"], 100);
}

// A scene whose file name is not UTF-8 (Linux names are bytes) still gets its stats and report written.
TEST(Cli, StatsOfASceneNamedInAnyBytesAreWritten) {
    const auto folder = test::temporaryFolder();
    const std::filesystem::path scene = folder / "caf\xe9.gltf";
    std::filesystem::copy_file(test::sourceDir() / "scenes/cornell.gltf", scene);
    const auto result =
        test::runVkrt("--scene " + quoted(scene) + " --device cpu --width 8 --spp 1 --quiet --out " +
                      quoted(folder / "x.png") + " --stats " + quoted(folder / "x.json") + " --report " +
                      quoted(folder / "r.json"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    for (const char* written : {"x.json", "r.json"}) {
        std::ifstream file(folder / written);
        nlohmann::json parsed;
        EXPECT_NO_THROW(parsed = nlohmann::json::parse(file)) << written;
        EXPECT_TRUE(parsed.is_object()) << written;
    }
}

// An output path that is a symbolic link is written through: the link stays, the file it names gets the image
// (the atomic write's rename used to replace the link with a file).
TEST(Cli, OutputThroughASymbolicLinkWritesTheFileItNames) {
    const auto folder = test::temporaryFolder();
    std::filesystem::create_directories(folder / "real");
    std::filesystem::create_symlink(folder / "real" / "target.pfm", folder / "link.pfm");
    std::filesystem::create_symlink(folder / "real" / "stats.json", folder / "stats.json");
    const auto result =
        test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --spp 1 --quiet --out " +
                      quoted(folder / "link.pfm") + " --stats " + quoted(folder / "stats.json"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    for (const char* link : {"link.pfm", "stats.json"}) {
        EXPECT_TRUE(std::filesystem::is_symlink(folder / link)) << link;
    }
    EXPECT_EQ(readImage((folder / "real" / "target.pfm").string()).width, 8);
    EXPECT_TRUE(std::filesystem::is_regular_file(folder / "real" / "stats.json"));
}

// An output path in a loop of symbolic links names no file: it is refused before the render, in one line, as
// bad usage, and the links stay as they were (the loop was replaced by a regular file, with exit 0).
TEST(Cli, OutputThroughALoopOfSymbolicLinksIsRefused) {
    const auto folder = test::temporaryFolder();
    std::filesystem::create_symlink("loop2.png", folder / "loop1.png");
    std::filesystem::create_symlink("loop1.png", folder / "loop2.png");
    const auto result = test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --spp 1 --out " +
                                      quoted(folder / "loop1.png"));
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_EQ(result.output.rfind("vkrt: error: --out: ", 0), 0u) << result.output;
    EXPECT_NE(result.output.find("(Too many levels of symbolic links)"), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    for (const auto& [link, target] :
         {std::pair{"loop1.png", "loop2.png"}, std::pair{"loop2.png", "loop1.png"}}) {
        ASSERT_TRUE(std::filesystem::is_symlink(folder / link)) << link;
        EXPECT_EQ(std::filesystem::read_symlink(folder / link), target) << link;
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 2) << "the links alone";
}

TEST(Cli, CameraOutOfRangeIsBadInput) {
    const auto folder = test::temporaryFolder();
    const auto result =
        test::runVkrt("--scene " + kCornell + " --camera 3 --out '" + (folder / "x.png").string() + "'");
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_NE(result.output.find("camera"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(folder / "x.png"));
}

TEST(Cli, SceneWithoutGeometryRendersTheBackground) {
    const auto folder = test::temporaryFolder();
    test::writeText(folder / "empty.gltf",
                    R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})");
    for (const char* device : {"gpu", "cpu"}) {
        const auto out = folder / (std::string(device) + ".pfm");
        const auto result =
            test::runVkrt("--scene " + quoted(folder / "empty.gltf") + " --device " + device +
                          " --width 8 --height 8 --spp 1 --background 0.25 --out " + quoted(out));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        EXPECT_NE(result.output.find("no triangles"), std::string::npos) << result.output;
        EXPECT_EQ(readImage(out.string()).at(3, 3), glm::vec3(0.25f));
    }
}

TEST(Cli, ListsDevices) {
    const auto result = test::runVkrt("--list-devices");
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(result.output.rfind("0: ", 0), 0u) << result.output;
    // Each device's memory heaps and types, as the buffers' placement reads them.
    EXPECT_NE(result.output.find("\n   heap 0: "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("; types: 0 "), std::string::npos) << result.output;
}

// A device index beyond the devices there are is bad usage, as an index out of range anywhere else (exit 2;
// it was 1, a runtime failure).
TEST(Cli, MissingDeviceIndexIsBadUsage) {
    const auto folder = test::temporaryFolder();
    const auto result =
        test::runVkrt("--scene " + kCornell + " --device-index 200 --out " + quoted(folder / "x.png"));
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_NE(result.output.find("--list-devices"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "x.png"));
}

// The scene loads while the device is made (prepared_render.cpp); a scene or camera that cannot be used is
// still the error reported (exit 2), ahead of a device that cannot be had.
TEST(Cli, BadSceneIsReportedBeforeAMissingDevice) {
    const auto folder = test::temporaryFolder();
    const auto broken = folder / "broken.gltf";
    std::ofstream(broken) << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [";
    const auto bad =
        test::runVkrt("--scene " + quoted(broken) + " --device-index 200 --out " + quoted(folder / "x.png"));
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_NE(bad.output.find("broken.gltf"), std::string::npos) << bad.output;
    EXPECT_EQ(bad.output.find("--list-devices"), std::string::npos) << bad.output;
    const auto camera = test::runVkrt("--scene " + kCornell + " --camera 99 --device-index 200 --out " +
                                      quoted(folder / "x.png"));
    EXPECT_EQ(camera.exitCode, 2) << camera.output;
    EXPECT_NE(camera.output.find("--camera 99"), std::string::npos) << camera.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "x.png"));
}

TEST(Cli, GpuRenderUnderValidationWritesGpuStats) {
    const auto folder = test::temporaryFolder();
    const auto stats = folder / "stats.json";
    const auto result =
        test::runVkrt("--scene " + kCornell + " --validate --width 32 --height 32 --spp 2 --out " +
                      quoted(folder / "c.png") + " --stats " + quoted(stats));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(result.output.find("validation"), std::string::npos) << result.output;
    std::ifstream file(stats);
    const nlohmann::json json = nlohmann::json::parse(file);
    EXPECT_EQ(json["device"], "gpu");
    for (const char* key :
         {"device_name", "driver", "gpu_ms", "features", "gpu_memory_bytes", "mrays_per_gpu_s"}) {
        EXPECT_TRUE(json.contains(key)) << key;
    }
    EXPECT_EQ(json["features"], nlohmann::json::array({"area_lights"}));
    EXPECT_EQ(json["rays"]["primary"], 32 * 32 * 2);
    EXPECT_GT(json["gpu_memory_bytes"].get<uint64_t>(), 0u);
    // Where the render's time went: the dispatches' wall time (at least their GPU time) and the copies of the
    // device's sums to the host, each within the render's time.
    const double renderMs = json["render_ms"].get<double>();
    const double dispatchMs = json["dispatches"]["total_ms"].get<double>();
    const double copyMs = json["memory"]["host_copy_ms"].get<double>();
    EXPECT_GE(dispatchMs, json["gpu_ms"].get<double>() * 0.99);
    EXPECT_GE(dispatchMs, json["dispatches"]["longest_ms"].get<double>());
    EXPECT_GT(copyMs, 0.0);
    EXPECT_LE(dispatchMs + copyMs + json["shader"]["pipeline_ms"].get<double>(), renderMs);
    // The renderer's making: within the render's time, and holding the pipeline's creation and the scene's
    // packing; the scene's buffers are written beside the pipeline's making, so only within the whole.
    const double setupMs = json["setup"]["total_ms"].get<double>();
    EXPECT_LE(setupMs + dispatchMs, renderMs);
    EXPECT_GE(setupMs, json["shader"]["pipeline_ms"].get<double>() + json["setup"]["pack_ms"].get<double>());
    EXPECT_GT(json["setup"]["scene_write_ms"].get<double>(), 0.0);
    EXPECT_LE(json["setup"]["scene_write_ms"].get<double>(), setupMs);
}

TEST(Cli, SceneAccessChoosesHowTheGpuReadsTheScene) {
    // --scene-access, a GPU diagnostic: each way is the one the stats report, and the image is the same.
    const auto folder = test::temporaryFolder();
    std::string first;
    for (const auto& [flag, name] :
         {std::pair{"texels", "texel buffers"}, std::pair{"storage", "storage buffers"},
          std::pair{"addresses", "device addresses"}}) {
        const auto image = folder / (std::string(flag) + ".exr"), stats = folder / "stats.json";
        const auto result =
            test::runVkrt("--scene " + kCornell + " --quiet --width 24 --height 24 --spp 2 " +
                          "--scene-access " + flag + " --out " + quoted(image) + " --stats " + quoted(stats));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        std::ifstream file(stats);
        EXPECT_EQ(nlohmann::json::parse(file)["scene_access"], name);
        std::ifstream in(image, std::ios::binary);
        const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        if (first.empty()) first = bytes;
        EXPECT_EQ(bytes, first) << flag;
    }
    const auto bad = test::runVkrt("--scene " + kCornell + " --scene-access fast");
    EXPECT_EQ(bad.exitCode, 2);
}

TEST(Cli, TimeLimitWritesTheImageWithFewerSamples) {
    const auto folder = test::temporaryFolder();
    const auto stats = folder / "stats.json";
    const auto result =
        test::runVkrt("--scene " + kCornell + " --quiet --width 16 --height 16 --spp 1000000 " +
                      "--time-limit 0.01 --out " + quoted(folder / "c.exr") + " --stats " + quoted(stats));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    std::ifstream file(stats);
    const nlohmann::json json = nlohmann::json::parse(file);
    EXPECT_GE(json["spp_max"].get<int>(), 1);  // the limit may end the first pass part way
    EXPECT_LT(json["spp_max"].get<int>(), 1000000);
    EXPECT_EQ(json["spp_requested"], 1000000);
    EXPECT_TRUE(std::filesystem::exists(folder / "c.exr"));
}

// The GPU's single-precision triangle test holds to 1e12 from the scene's middle: a scene that reaches 1e30
// is refused there with one line naming the way out (its triangles vanished silently), and the CPU renders
// it.
TEST(Cli, SceneBeyondTheGpusReachIsRefusedOnTheGpuAndRenderedOnTheCpu) {
    const auto folder = test::temporaryFolder();
    const auto scene = folder / "huge.gltf";
    test::writeText(scene, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 4]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}, "doubleSided": true,
                       "extensions": {"KHR_materials_unlit": {}}}],
        "extensionsUsed": ["KHR_materials_unlit"],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-1.0000000150474662e+30, -1.0000000150474662e+30, -1.0],
                       "max": [1.0000000150474662e+30, 1.0000000150474662e+30, -1.0]},
                      {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
        "buffers": [{"byteLength": 48, "uri": "data:application/octet-stream;base64,yvJJ8crySfEAAIC/yvJJccrySfEAAIC/AAAAAMrySXEAAIC/AAAAAAEAAAACAAAA"}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.001}}]})");
    const auto gpu = test::runVkrt("--scene " + quoted(scene) + " --device gpu --width 8 --spp 1 --out " +
                                   quoted(folder / "gpu.pfm"));
    EXPECT_EQ(gpu.exitCode, 2) << gpu.output;
    EXPECT_NE(gpu.output.find("the GPU's single-precision tests hold to 1e12 (--device cpu renders it)"),
              std::string::npos)
        << gpu.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "gpu.pfm"));
    const auto cpu = test::runVkrt("--scene " + quoted(scene) + " --device cpu --width 8 --spp 1 --out " +
                                   quoted(folder / "cpu.pfm"));
    ASSERT_EQ(cpu.exitCode, 0) << cpu.output;
    for (const glm::vec3& pixel : readImage((folder / "cpu.pfm").string()).pixels)
        EXPECT_NEAR(pixel.x, 1.0f, 1e-6f);
    // The test's products are of three coordinates relative to the ray's origin: a unit triangle seen from
    // 1e13 away vanished on the GPU too (the CPU saw it), and so did one 1e13 across.
    for (const double far : {1e13, 1e11}) {
        test::GltfDocument d;
        const int positions = d.floats({-1, -1, 0, 1, -1, 0, 0, 1, 0}, "VEC3");
        d.json["accessors"][positions]["min"] = {-1, -1, 0};
        d.json["accessors"][positions]["max"] = {1, 1, 0};
        d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}};
        d.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1e-12}, {"znear", 1.0}}}}};
        d.node({{"mesh", 0}});
        d.node({{"camera", 0}, {"translation", {0.0, 0.0, far}}});
        const auto farScene = folder / "far.gltf";
        d.write(farScene);
        const auto run = test::runVkrt("--scene " + quoted(farScene) +
                                       " --device gpu --width 8 --spp 1 --out " + quoted(folder / "far.pfm"));
        if (far > kGpuReach) {
            EXPECT_EQ(run.exitCode, 2) << run.output;
            EXPECT_NE(run.output.find("the camera is 1e+13 units from the scene's middle"), std::string::npos)
                << run.output;
        } else {
            ASSERT_EQ(run.exitCode, 0) << run.output;
            EXPECT_GT(readImage((folder / "far.pfm").string()).at(4, 4).x, 0.0f) << "the triangle is seen";
        }
    }
}

// At the other end, the test's products are about the cube of the scene's size: a triangle 1e-18 across seen
// from as near came out black on the GPU (they underflowed) while the CPU saw it. The GPU refuses a scene
// with triangles that lies within 1e-12 of its middle, camera and all; one 1e-11 across renders.
TEST(Cli, SceneBelowTheGpusReachIsRefusedOnTheGpuAndRenderedOnTheCpu) {
    const auto folder = test::temporaryFolder();
    for (const double size : {1e-18, 1e-11}) {
        SCOPED_TRACE(size);
        test::GltfDocument d;
        const int positions = d.floats({-1, -1, 0, 1, -1, 0, 0, 1, 0}, "VEC3");
        d.json["accessors"][positions]["min"] = {-1, -1, 0};
        d.json["accessors"][positions]["max"] = {1, 1, 0};
        d.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", positions}}}, {"material", 0}}}}}};
        d.json["materials"] = {
            {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}}};  // matte, lit by the ambient
        d.json["cameras"] = {
            {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01 * size}}}}};
        d.node({{"mesh", 0}, {"scale", {size, size, size}}});
        d.node({{"camera", 0}, {"translation", {0.0, 0.0, 3.0 * size}}});
        const auto scene = folder / "tiny.gltf";
        d.write(scene);
        const std::string options =
            "--scene " + quoted(scene) + " --width 8 --spp 1 --ambient 1 --integrator whitted";
        const auto cpu = test::runVkrt(options + " --device cpu --out " + quoted(folder / "cpu.pfm"));
        ASSERT_EQ(cpu.exitCode, 0) << cpu.output;
        EXPECT_GT(readImage((folder / "cpu.pfm").string()).at(4, 4).x, 0.0f) << "the triangle is seen";
        const auto gpu = test::runVkrt(options + " --device gpu --out " + quoted(folder / "gpu.pfm"));
        if (size < kGpuSmallestReach) {
            EXPECT_EQ(gpu.exitCode, 2) << gpu.output;
            EXPECT_NE(
                gpu.output.find("the GPU's single-precision triangle test holds from 1e-12 (--device cpu "
                                "renders it)"),
                std::string::npos)
                << gpu.output;
        } else {
            ASSERT_EQ(gpu.exitCode, 0) << gpu.output;
            EXPECT_GT(readImage((folder / "gpu.pfm").string()).at(4, 4).x, 0.0f) << "the triangle is seen";
        }
    }
}

TEST(Cli, RendersEveryFormatAndWritesStats) {
    const auto folder = test::temporaryFolder();
    for (const char* name : {"c.png", "c.exr", "c.pfm"}) {
        const auto out = folder / name;
        const auto stats = folder / "stats.json";
        const auto result =
            test::runVkrt("--scene " + kCornell + " --device cpu --width 24 --height 16 --spp 2 --out '" +
                          out.string() + "' --stats '" + stats.string() + "'");
        ASSERT_EQ(result.exitCode, 0) << result.output;
        ASSERT_TRUE(std::filesystem::exists(out)) << name;
        if (std::string(name) != "c.png") {
            const Image image = readImage(out.string());
            EXPECT_EQ(image.width, 24);
            EXPECT_EQ(image.height, 16);
        }
        std::ifstream file(stats);
        const nlohmann::json json = nlohmann::json::parse(file);
        for (const char* key :
             {"scene", "device", "width", "height", "spp", "render_ms", "mrays_per_s", "nonfinite_samples"}) {
            EXPECT_TRUE(json.contains(key)) << key;
        }
        for (const char* key : {"build_ms", "nodes", "depth", "sah_cost"})
            EXPECT_TRUE(json["bvh"].contains(key)) << key;
        for (const char* key : {"primary", "shadow", "secondary"})
            EXPECT_TRUE(json["rays"].contains(key)) << key;
        EXPECT_EQ(json["rays"]["primary"], 24 * 16 * 2);
        EXPECT_EQ(json["device"], "cpu");
        EXPECT_EQ(json["nonfinite_samples"], 0);
    }
}

TEST(Cli, IntegratorAndDepthAreChosenAndRecorded) {
    // Paths by default, 64 deep; Whitted when asked, 8 deep, and at most 24 (exit 2 beyond, before rendering).
    const auto folder = test::temporaryFolder();
    const auto stats = folder / "stats.json";
    const std::string common = "--scene " + kCornell + " --device cpu --width 8 --spp 1 --out '" +
                               (folder / "c.exr").string() + "' --stats '" + stats.string() + "'";
    struct Case {
        std::string options;
        const char* integrator;
        int depth;
    };
    for (const Case& c : {Case{"", "path", 64}, Case{" --integrator whitted", "whitted", 8},
                          Case{" --max-depth 500", "path", 500}, Case{" --integrator whitted --max-depth 24", "whitted", 24}}) {
        const auto result = test::runVkrt(common + c.options);
        ASSERT_EQ(result.exitCode, 0) << c.options << ": " << result.output;
        std::ifstream file(stats);
        const nlohmann::json json = nlohmann::json::parse(file);
        EXPECT_EQ(json["integrator"], c.integrator) << c.options;
        EXPECT_EQ(json["max_depth"], c.depth) << c.options;
    }
    std::filesystem::remove(folder / "c.exr");
    const auto deep = test::runVkrt(common + " --integrator whitted --max-depth 25");
    EXPECT_EQ(deep.exitCode, 2) << deep.output;
    EXPECT_NE(deep.output.find("Whitted"), std::string::npos) << deep.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "c.exr"));
}

TEST(Cli, EnvironmentLightsTheSceneAndIsRecordedInTheStats) {
    const auto folder = test::temporaryFolder();
    // The sky map as .hdr, and the same radiance as .exr (written through vkrt's own EXR writer).
    const std::string hdr = (test::sourceDir() / "scenes/sky.hdr").string();
    const auto exr = folder / "sky.exr";
    writeImage(readRadianceImage(hdr), exr.string());
    for (const std::string& map : {hdr, exr.string()}) {
        const auto stats = folder / "stats.json";
        const auto result = test::runVkrt("--scene " + quoted(test::sourceDir() / "scenes/environment.gltf") +
                                          " --device cpu --width 16 --spp 1 --environment " +
                                          quoted(std::filesystem::path(map)) +
                                          " --environment-rotation 30 --environment-strength 2 --out " +
                                          quoted(folder / "e.pfm") + " --stats " + quoted(stats));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        EXPECT_EQ(result.output.find("no lights"), std::string::npos) << "the environment lights the scene";
        std::ifstream file(stats);
        const nlohmann::json json = nlohmann::json::parse(file);
        EXPECT_EQ(json["environment"], (nlohmann::json{{"file", map},
                                                       {"width", 64},
                                                       {"height", 32},
                                                       {"rotation_degrees", 30.0},
                                                       {"strength", 2.0}}));
        // Rays that leave the scene at the top of the picture see the sky, not the black background.
        EXPECT_GT(readImage((folder / "e.pfm").string()).at(8, 0).z, 0.5f);
    }
}

// A scene of one perspective camera and nothing else, written in `folder`.
std::filesystem::path cameraOnlyScene(const std::filesystem::path& folder) {
    test::GltfDocument d;
    d.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}};
    d.node({{"camera", 0}});
    d.floats({0.0f}, "SCALAR");  // the document's buffer may not be empty
    const auto scene = folder / "camera-only.gltf";
    d.write(scene);
    return scene;
}

// The uniform environment that lights a scene without lights (radiance 1), or paths under --ambient, is
// recorded as that radiance: it was recorded as a 16 x 8 map read from a file named "neutral", the same
// whatever the ambient radiance.
TEST(Cli, UniformEnvironmentIsRecordedAsItsRadiance) {
    const auto folder = test::temporaryFolder();
    const auto scene = cameraOnlyScene(folder);
    const auto stats = folder / "stats.json";
    for (const auto& [options, radiance] : {std::pair<std::string, nlohmann::json>{"", {1.0, 1.0, 1.0}},
                                            {" --ambient 0.25", {0.25, 0.25, 0.25}}}) {
        const auto result =
            test::runVkrt("--scene " + quoted(scene) + " --device cpu --width 4 --spp 1" + options +
                          " --out " + quoted(folder / "e.pfm") + " --stats " + quoted(stats));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        std::ifstream file(stats);
        EXPECT_EQ(nlohmann::json::parse(file)["environment"],
                  (nlohmann::json{{"uniform_radiance", radiance}}))
            << options;
    }
}

TEST(Cli, HeightFollowsTheCameraAspectRatio) {
    const auto folder = test::temporaryFolder();
    const auto out = folder / "c.pfm";
    const auto result =
        test::runVkrt("--scene " + kCornell + " --quiet --width 20 --spp 1 --out '" + out.string() + "'");
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(readImage(out.string()).height, 20);  // the Cornell camera's aspect ratio is 1
}

TEST(Cli, WithoutACameraTheImageIsSquare) {
    const auto folder = test::temporaryFolder();
    test::writeText(folder / "empty.gltf",
                    R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})");
    const auto out = folder / "e.pfm";
    const auto result = test::runVkrt("--scene " + quoted(folder / "empty.gltf") +
                                      " --device cpu --quiet --width 24 --spp 1 --out " + quoted(out));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(readImage(out.string()).height, 24);
}

// Emissive spheres light a scene as much as lights and emissive triangles do: no ambient fallback.
TEST(Cli, SceneLitByEmissiveSpheresGetsNoLightsWarning) {
    const auto folder = test::temporaryFolder();
    const auto result =
        test::runVkrt("--scene " + quoted(test::sourceDir() / "scenes/glossy.gltf") +
                      " --device cpu --width 16 --height 10 --spp 1 --out " + quoted(folder / "g.pfm"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(result.output.find("no lights"), std::string::npos) << result.output;
    // A scene with nothing in it does get the warning.
    test::writeText(folder / "empty.gltf",
                    R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})");
    const auto empty =
        test::runVkrt("--scene " + quoted(folder / "empty.gltf") +
                      " --device cpu --width 4 --height 4 --spp 1 --out " + quoted(folder / "e.pfm"));
    ASSERT_EQ(empty.exitCode, 0) << empty.output;
    EXPECT_NE(empty.output.find("the scene has no lights"), std::string::npos) << empty.output;
}

TEST(Cli, EveryThirdPartySceneRenders) {
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal();
    const auto folder = test::temporaryFolder();
    for (const auto& file : test::gltfFilesUnder(test::scenesReal())) {
        const auto out = folder / "x.pfm";
        const auto result = test::runVkrt("--scene " + quoted(file) +
                                          " --quiet --width 12 --height 8 --spp 1 --out " + quoted(out));
        EXPECT_EQ(result.exitCode, 0) << file << ": " << result.output;
        EXPECT_TRUE(std::filesystem::exists(out)) << file;
        std::filesystem::remove(out);
    }
}

std::vector<std::vector<double>> readCsv(const std::filesystem::path& path) {
    std::ifstream file(path);
    std::string line;
    std::getline(file, line);  // header
    std::vector<std::vector<double>> rows;
    while (std::getline(file, line)) {
        std::vector<double> row;
        std::stringstream fields(line);
        std::string field;
        // An empty field (a CPU render's GPU time) is NaN.
        while (std::getline(fields, field, ','))
            row.push_back(field.empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(field));
        rows.push_back(row);
    }
    return rows;
}

// The mean of more samples converges to the reference, for every distributed effect: soft shadows
// (cornell), glossy lobes with MIS (glossy), motion blur and depth of field, on both devices.
TEST(Cli, ReportRecordsErrorAtEveryDoublingOfSamples) {
    const auto folder = test::temporaryFolder();
    for (const char* scene : {"cornell.gltf", "glossy.gltf", "motion-blur.gltf", "dof.gltf"}) {
        const std::string path = quoted(test::sourceDir() / "scenes" / scene);
        const auto reference = folder / "reference.pfm";
        ASSERT_EQ(test::runVkrt("--scene " + path +
                                " --quiet --device cpu --width 24 --height 16 --spp 1024 --seed 9 --out " +
                                quoted(reference))
                      .exitCode,
                  0);
        for (const char* device : {"gpu", "cpu"}) {
            SCOPED_TRACE(std::string(scene) + " " + device);
            const auto report = folder / "report.csv";
            const auto stats = folder / "stats.json";
            const auto result = test::runVkrt("--scene " + path + " --quiet --device " + device +
                                              " --width 24 --height 16 --spp 32 --reference " +
                                              quoted(reference) + " --report " + quoted(report) + " --out " +
                                              quoted(folder / "x.pfm") + " --stats " + quoted(stats));
            ASSERT_EQ(result.exitCode, 0) << result.output;
            const auto rows = readCsv(report);
            // Render time counts from the renderer's set-up on, as the stats' render_ms does: the GPU's
            // pipeline creation (its setup.total_ms) was left out, which favoured the GPU against the CPU.
            std::ifstream statsFile(stats);
            const nlohmann::json json = nlohmann::json::parse(statsFile);
            if (std::string(device) == "gpu") {
                EXPECT_GT(rows.front()[1], json["setup"]["total_ms"].get<double>());
            }
            EXPECT_LE(rows.back()[1], json["render_ms"].get<double>());
            ASSERT_EQ(rows.size(), 6u);  // 1, 2, 4, 8, 16, 32 samples
            for (size_t i = 0; i < rows.size(); ++i) {
                EXPECT_EQ(rows[i][0], static_cast<double>(1u << i));
                // The GPU's time; none for the CPU reference (it wrote 0, read as a measurement).
                if (std::string(device) == "gpu") {
                    EXPECT_GT(rows[i][2], 0.0);
                } else {
                    EXPECT_TRUE(std::isnan(rows[i][2])) << rows[i][2];
                }
                if (i > 0) {
                    EXPECT_GT(rows[i][1], rows[i - 1][1]) << "render time grows";
                }
            }
            EXPECT_LT(rows.back()[3], 0.25 * rows.front()[3])
                << "RMSE falls at least fourfold from 1 to 32 samples";
        }
    }
}

// Formats are chosen by the extension in any case, for reports as for images: "r.CSV" was refused where
// "x.PFM" was written.
TEST(Cli, ReportExtensionsAreReadInAnyCase) {
    const auto folder = test::temporaryFolder();
    const auto reference = folder / "reference.PFM", report = folder / "report.CSV";
    const std::string size = " --device cpu --width 8 --height 8 --quiet";
    ASSERT_EQ(test::runVkrt("--scene " + kCornell + size + " --spp 16 --out " + quoted(reference)).exitCode,
              0);
    const auto run =
        test::runVkrt("--scene " + kCornell + size + " --spp 4 --reference " + quoted(reference) +
                      " --report " + quoted(report) + " --out " + quoted(folder / "x.pfm"));
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_EQ(test::readText(report).rfind("samples,render_ms,", 0), 0u) << "written as CSV";
}

// A render the time limit stops between two checkpoints ends its report with the image it writes: the last
// checkpoint once was the one before, so the report, and the error vkrt printed, did not describe the image.
TEST(Cli, ReportOfARenderStoppedByTheTimeLimitEndsWithTheImageWritten) {
    const auto folder = test::temporaryFolder();
    const auto reference = folder / "reference.pfm";
    ASSERT_EQ(
        test::runVkrt("--scene " + kCornell +
                      " --quiet --device cpu --width 16 --height 16 --spp 256 --out " + quoted(reference))
            .exitCode,
        0);
    for (const char* device : {"gpu", "cpu"}) {
        SCOPED_TRACE(device);
        const auto report = folder / "report.json", image = folder / "x.pfm";
        const auto result =
            test::runVkrt("--scene " + kCornell + " --quiet --device " + device +
                          " --width 16 --height 16 --spp 1000000 --time-limit 0.3 --reference " +
                          quoted(reference) + " --report " + quoted(report) + " --out " + quoted(image));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        std::ifstream file(report);
        const nlohmann::json json = nlohmann::json::parse(file);
        const nlohmann::json& last = json["checkpoints"].back();
        EXPECT_EQ(last["samples"], json["spp"]) << "the samples every pixel has";
        const Image written = readImage(image.string()), expected = readImage(reference.string());
        double sum = 0.0;
        for (size_t i = 0; i < written.pixels.size(); ++i) {
            for (int c = 0; c < 3; ++c) {
                const double d = double(written.pixels[i][c]) - double(expected.pixels[i][c]);
                sum += d * d;
            }
        }
        EXPECT_NEAR(last["rmse"].get<double>(), std::sqrt(sum / (3.0 * written.pixels.size())), 1e-9);
    }
}

TEST(Cli, ReportWithoutReferenceMakesOneAndSaysSo) {
    const auto folder = test::temporaryFolder();
    const auto report = folder / "report.json";
    const auto result = test::runVkrt("--scene " + kCornell + " --width 16 --spp 4 --report " +
                                      quoted(report) + " --out " + quoted(folder / "x.png"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    std::ifstream file(report);
    const nlohmann::json json = nlohmann::json::parse(file);
    EXPECT_NE(json["reference"].get<std::string>().find("64 spp, seed 1"), std::string::npos)
        << json["reference"];
    EXPECT_EQ(json["checkpoints"].size(), 3u);
    // What made the image, as the stats name it: each integrator converges to its own image.
    EXPECT_EQ(json.value("integrator", ""), "path");
    EXPECT_EQ(json.value("spp_requested", 0), 4);
    EXPECT_EQ(json.value("max_depth", 0), 64);
    EXPECT_EQ(json.value("light_samples", 0), 1);
    // The reference renders all its samples whatever the time limit (a reference cut short would not be one):
    // vkrt says so, since with many samples it can take far longer than the limit.
    const auto limited =
        test::runVkrt("--scene " + kCornell + " --width 16 --spp 4 --time-limit 60 --report " +
                      quoted(report) + " --out " + quoted(folder / "x.png"));
    ASSERT_EQ(limited.exitCode, 0) << limited.output;
    EXPECT_NE(limited.output.find("--time-limit does not bound this reference (64 spp)"), std::string::npos)
        << limited.output;
    // After the largest seed, the reference's is 0: one that --seed takes, so it can be rendered again (it
    // was 2147483648, which --seed refuses).
    const auto last =
        test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --spp 1 --seed 2147483647 --report " +
                      quoted(report) + " --out " + quoted(folder / "x.png"));
    ASSERT_EQ(last.exitCode, 0) << last.output;
    EXPECT_NE(last.output.find("vkrt: reference: cpu render made by this run, 16 spp, seed 0\n"),
              std::string::npos)
        << last.output;
}

TEST(Cli, ReferenceOfTheWrongSizeIsBadInput) {
    const auto folder = test::temporaryFolder();
    ASSERT_EQ(test::runVkrt("--scene " + kCornell + " --quiet --device cpu --width 8 --spp 1 --out " +
                            quoted(folder / "r.pfm"))
                  .exitCode,
              0);
    const auto result =
        test::runVkrt("--scene " + kCornell + " --width 16 --spp 1 --reference " + quoted(folder / "r.pfm") +
                      " --report " + quoted(folder / "r.csv") + " --out " + quoted(folder / "x.png"));
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "x.png"));
    EXPECT_FALSE(std::filesystem::exists(folder / "r.csv"));
}

}  // namespace
// Tone mapping changes the PNG and only the PNG: linear formats store the radiance as rendered.
TEST(Cli, ToneMapAppliesToPngOnly) {
    const auto folder = test::temporaryFolder();
    auto render = [&](const char* toneMap, const char* file) {
        const auto result = test::runVkrt("--scene " + kCornell + " --device cpu --width 24 --height 24 --spp 1 " +
                                          "--tonemap " + toneMap + " --out " + quoted(folder / file));
        EXPECT_EQ(result.exitCode, 0) << result.output;
        std::ifstream in(folder / file, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_NE(render("clamp", "clamp.png"), render("aces", "aces.png"));
    EXPECT_NE(render("clamp", "clamp.png"), render("pbr-neutral", "neutral.png"));
    EXPECT_EQ(render("clamp", "clamp.pfm"), render("aces", "aces.pfm"));
}

// Where stderr is no terminal (a log, mpirun's forwarding, which drew no bar at all) progress comes as a line
// now and then, none at the end; here every update is past the interval.
TEST(Progress, WithoutATerminalLinesSayHowFarTheRenderIs) {
    std::FILE* log = std::tmpfile();
    ASSERT_NE(log, nullptr);
    {
        ProgressBar progress("gpu", true, log, std::chrono::milliseconds(0));
        progress.update(1, 4);
        progress.update(3, 4);
        progress.update(4, 4);
        progress.finish();
        ProgressBar quiet("cpu", false, log, std::chrono::milliseconds(0));
        quiet.update(1, 4);
    }
    std::rewind(log);
    std::string text;
    for (int c; (c = std::fgetc(log)) != EOF;) text += static_cast<char>(c);
    std::fclose(log);
    EXPECT_EQ(text.find('\r'), std::string::npos) << text;
    EXPECT_NE(text.find("vkrt: gpu 25.0% after "), std::string::npos) << text;
    EXPECT_NE(text.find("vkrt: gpu 75.0% after "), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
}

// Options the run makes no use of are said to, one line each (they were taken silently); used, nothing is
// said.
TEST(Cli, OptionsThatDoNothingAreSaid) {
    const auto folder = test::temporaryFolder();
    const auto unused = test::runVkrt(
        "--scene " + kCornell + " --device cpu --width 8 --height 8 --spp 1 " +
        "--validate --scene-access texels --max-device-memory 1G --environment-strength 2 " +
        "--exposure 1 --tonemap aces --focus-distance 3 --shutter 0 1 --out " + quoted(folder / "a.pfm"));
    ASSERT_EQ(unused.exitCode, 0) << unused.output;
    for (const char* said :
         {"--validate is for the GPU; --device cpu ignores it", "--scene-access is for the GPU",
          "--max-device-memory is for the GPU", "--environment-strength does nothing without --environment",
          "--exposure is for PNG output", "--tonemap is for PNG output"}) {
        EXPECT_NE(unused.output.find(std::string("vkrt: warning: ") + said), std::string::npos)
            << said << "\n"
            << unused.output;
    }
    for (const char* said : {"cornell.gltf: --focus-distance focuses a lens, and the camera is a pinhole",
                             "cornell.gltf: --shutter: the file has no animations, so nothing moves"}) {
        EXPECT_NE(unused.output.find(said), std::string::npos) << said << "\n" << unused.output;
    }
    const auto used =
        test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --height 8 --spp 1 " +
                      "--exposure 1 --tonemap aces --aperture 0.01 --focus-distance 3 --environment " +
                      quoted(test::sourceDir() / "scenes/sky.hdr") + " --environment-strength 2 --out " +
                      quoted(folder / "b.png"));
    ASSERT_EQ(used.exitCode, 0) << used.output;
    EXPECT_EQ(used.output.find("warning"), std::string::npos) << used.output;
    const auto background = test::runVkrt(
        "--scene " + kCornell + " --device cpu --width 8 --height 8 --spp 1 " + "--environment " +
        quoted(test::sourceDir() / "scenes/sky.hdr") + " --background 0.5 --out " + quoted(folder / "c.pfm"));
    ASSERT_EQ(background.exitCode, 0) << background.output;
    EXPECT_NE(background.output.find("vkrt: warning: --background does nothing with --environment"),
              std::string::npos)
        << background.output;
}

// A write that fails says why: a full disk (here /dev/full, which takes nothing) was "cannot write" alone.
TEST(Cli, FailedWritesSayWhy) {
    const auto folder = test::temporaryFolder();
    const auto run =
        test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --height 8 --spp 1 --out " +
                      quoted(folder / "a.pfm") + " --stats /dev/full");
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_NE(run.output.find("vkrt: error: /dev/full: cannot write (No space left on device)"),
              std::string::npos)
        << run.output;
}

// A file-size limit (`ulimit -f`) that the image passes makes its write fail, said in one line (exit 1), with
// no temporary file left: vkrt was ended by SIGXFSZ with the image half written under its temporary name. The
// image is 256 x 256 PFM, 768 KiB; the limit, 4 blocks (2 KiB in dash, 4 in bash).
TEST(Cli, FileSizeLimitFailsTheWriteAndLeavesNothing) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "keep.pfm";
    const auto run = test::runCommand(
        "sh -c 'ulimit -f 4; exec \"$0\" \"$@\"' " + quoted(VKRT_BINARY) + " --scene " + kCornell +
        " --device cpu --width 256 --height 256 --spp 1 --quiet --out " + quoted(image));
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_NE(run.output.find("vkrt: error: " + image.string() + ": cannot write (File too large)"),
              std::string::npos)
        << run.output;
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 0) << "no temporary file left";
}

// A reader of vkrt's messages that has gone (`vkrt ... 2>&1 | head -1`, here a reader that exits at once)
// does not end vkrt: its writes to stderr fail, and the image is written and the exit code 0, on both
// devices. It ended by SIGPIPE (exit 141) at its first message, the last line after the image or a progress
// line mid-render.
TEST(Cli, AReaderOfTheMessagesThatHasGoneEndsNothing) {
    const auto folder = test::temporaryFolder();
    for (const std::string device : {"cpu", "gpu"}) {
        const auto image = folder / (device + ".pfm");
        const test::CommandResult run = test::runCommand(
            "bash -c \"'" + std::string(VKRT_BINARY) + "' --scene " + kCornell + " --device " + device +
            " --width 8 --height 8 --spp 1 --out " + quoted(image) + " 2> >(exit 0); echo exit=\\$?\"");
        EXPECT_NE(run.output.find("exit=0"), std::string::npos) << device << ": " << run.output;
        EXPECT_TRUE(std::filesystem::exists(image)) << device;
    }
}

// The outputs are written all or none: a stats file that cannot be written (/dev/full) leaves the image an
// earlier run wrote as it was, and no temporary file, where the new image replaced it beside the old stats.
TEST(Cli, OutputsAreWrittenAllOrNone) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "a.pfm";
    test::writeText(image, "an earlier run's image");
    const auto run =
        test::runVkrt("--scene " + kCornell + " --device cpu --width 8 --height 8 --spp 1 --out " +
                      quoted(image) + " --stats /dev/full");
    EXPECT_EQ(run.exitCode, 1) << run.output;
    std::ifstream file(image);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(file), {}), "an earlier run's image");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1) << "no temporary file left";
}

// An output replaces an earlier file with that file's permissions: a private image (0600) stayed private,
// where the new one was 0644.
TEST(Cli, OutputsKeepThePermissionsOfTheFilesTheyReplace) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "private.pfm";
    test::writeText(image, "an earlier run's image");
    const auto ownerOnly = std::filesystem::perms::owner_read | std::filesystem::perms::owner_write;
    std::filesystem::permissions(image, ownerOnly);
    const auto run = test::runVkrt("--scene " + kCornell +
                                   " --device cpu --width 8 --height 8 --spp 1 --out " + quoted(image));
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_EQ(std::filesystem::status(image).permissions(), ownerOnly);
    EXPECT_GT(std::filesystem::file_size(image), 100u) << "the new image";
}

// An output the user cannot replace is refused before the render, as bad usage: a file read-only to them (it
// was replaced, since a rename asks only the folder), or another user's in a folder with the sticky bit, like
// /tmp (the rename failed after the whole render, exit 1). Run as a user other than the files' owner (nobody,
// when the test runs as root).
TEST(Cli, OutputsTheUserCannotReplaceAreRefusedBeforeTheRender) {
    const std::string as = geteuid() == 0 ? "runuser -u nobody -- " : "";
    const auto folder = test::temporaryFolder();
    std::filesystem::permissions(folder, std::filesystem::perms::all | std::filesystem::perms::sticky_bit);
    // nobody must reach vkrt, the scene and the folder (a checkout under /root, or a private TMPDIR, keeps
    // them out).
    if (!as.empty() && test::runCommand(as + "test -x " + quoted(VKRT_BINARY) + " -a -r " + kCornell +
                                        " -a -w " + quoted(folder))
                               .exitCode != 0) {
        GTEST_SKIP() << "no user nobody that can run vkrt here";
    }
    const auto readOnly = folder / "read-only.pfm";
    test::writeText(readOnly, "kept");
    std::filesystem::permissions(readOnly, std::filesystem::perms::owner_read |
                                               std::filesystem::perms::group_read |
                                               std::filesystem::perms::others_read);
    const auto theirs = folder / "theirs.pfm";
    test::writeText(theirs, "kept");
    std::filesystem::permissions(theirs, std::filesystem::perms::all & ~std::filesystem::perms::owner_exec &
                                             ~std::filesystem::perms::group_exec &
                                             ~std::filesystem::perms::others_exec);
    const std::string command = as + std::string(VKRT_BINARY) + " --scene " + kCornell +
                                " --device cpu --width 8 --height 8 --spp 1 --out ";
    if (geteuid() != 0) {
        const auto own = test::runCommand(command + quoted(readOnly));
        EXPECT_EQ(own.exitCode, 2) << own.output;
        EXPECT_NE(own.output.find("read-only.pfm: is read-only"), std::string::npos) << own.output;
        return;  // the files are this user's own: the sticky bit keeps nothing from them
    }
    const auto readOnlyRun = test::runCommand(command + quoted(readOnly));
    EXPECT_EQ(readOnlyRun.exitCode, 2) << readOnlyRun.output;
    EXPECT_NE(readOnlyRun.output.find("--out: " + readOnly.string() + ": is read-only"), std::string::npos)
        << readOnlyRun.output;
    const auto theirsRun =
        test::runCommand(command + quoted(folder / "new.pfm") + " --stats " + quoted(theirs));
    EXPECT_EQ(theirsRun.exitCode, 2) << theirsRun.output;
    EXPECT_NE(theirsRun.output.find("theirs.pfm: belongs to another user"), std::string::npos)
        << theirsRun.output;
    for (const auto& kept : {readOnly, theirs}) {
        std::ifstream file(kept);
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(file), {}), "kept") << kept;
    }
    EXPECT_FALSE(std::filesystem::exists(folder / "new.pfm")) << "nothing written";
}

// The stats say how much texture memory a scene holds: textures.gltf has a 2x2, a 16x1 and a 4x1 RGBA8 texture,
// each with its mipmaps down to 1x1 (1; 8, 4, 2 and 1; 2 and 1 texels).
TEST(Cli, StatsReportTextureMemory) {
    const auto folder = test::temporaryFolder();
    const auto stats = folder / "stats.json";
    const auto result = test::runVkrt("--scene " + quoted(test::sourceDir() / "scenes/textures.gltf") +
                                      " --device cpu --width 16 --height 10 --spp 1 --out " +
                                      quoted(folder / "t.pfm") + " --stats " + quoted(stats));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    std::ifstream file(stats);
    EXPECT_EQ(nlohmann::json::parse(file)["texture_bytes"], ((2 * 2 + 1) + (16 + 8 + 4 + 2 + 1) + (4 + 2 + 1)) * 4);
}

// Radiance near float's limit (an environment of strength 3e38, seen by every pixel of an empty scene): the
// GPU's single-precision sums would overflow (their Kahan compensation then made NaN pixels while no sample
// was counted as lost); samples that would take a sum beyond float's range are left out and counted instead,
// and vkrt warns. Every pixel keeps its first sample. The CPU's double sums hold them all.
TEST(Cli, RadianceBeyondFloatSumsIsLeftOutAndCounted) {
    const auto folder = test::temporaryFolder();
    // A uniform map of radiance 1 at strength 3e38: every texel stays a float, four samples' sum does not.
    Image uniform(8, 4);
    for (glm::vec3& texel : uniform.pixels) texel = glm::vec3(1.0f);
    writeImage(uniform, (folder / "uniform.exr").string());
    const auto scene = cameraOnlyScene(folder);
    for (const char* device : {"gpu", "cpu"}) {
        SCOPED_TRACE(device);
        const auto image = folder / (std::string(device) + ".pfm");
        const auto stats = folder / (std::string(device) + ".json");
        const auto result = test::runVkrt(
            "--scene " + quoted(scene) + " --environment " + quoted(folder / "uniform.exr") +
            " --environment-strength 3e38 --device " + device + " --width 16 --height 10 --spp 4 --out " +
            quoted(image) + " --stats " + quoted(stats));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        const Image pixels = readImage(image.string());
        for (const glm::vec3& p : pixels.pixels)
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        std::ifstream file(stats);
        const uint64_t lost = nlohmann::json::parse(file)["nonfinite_samples"];
        if (std::string(device) == "gpu") {
            EXPECT_GT(lost, 0u);
            EXPECT_NE(result.output.find(
                          "samples were not finite in single precision (or would overflow their pixel's sum"),
                      std::string::npos)
                << result.output;
        } else {
            EXPECT_EQ(lost, 0u);
        }
    }
}

// 20,000 point lights over a quad: on lavapipe every sample's light loop runs past llvmpipe's loop budget and
// is left out. Where the quad fills the view the image would be black throughout, and where it fills half the
// view that half would be (both were written so, with exit 0 and a warning): vkrt says why and writes neither
// the image nor the stats. The CPU reference renders both.
TEST(Cli, RenderThatKeepsNoSampleOfSomePixelsWritesNothing) {
    const auto folder = test::temporaryFolder();
    for (const float right : {4.0f, 0.0f}) {
        const bool fills = right > 0.0f;
        SCOPED_TRACE(fills ? "the quad fills the view" : "the quad fills its left half");
        test::GltfDocument d;
        const int positions = d.floats({-4, -4, 0, right, -4, 0, right, 4, 0, -4, 4, 0}, "VEC3");
        d.json["accessors"][positions]["min"] = {-4, -4, 0};
        d.json["accessors"][positions]["max"] = {right, 4, 0};
        const int indices = d.unsignedShorts({0, 1, 2, 0, 2, 3}, "SCALAR");
        d.json["meshes"] = {
            {{"primitives", {{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}}}}};
        d.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.01}}}}};
        d.node({{"mesh", 0}});
        d.node({{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
        constexpr int kLights = 20000;
        nlohmann::json lights = nlohmann::json::array();
        for (int i = 0; i < kLights; ++i) {
            lights.push_back({{"type", "point"}, {"intensity", 10.0 / kLights}});
            d.node({{"translation", {std::cos(i), std::sin(i), 1.0}},
                    {"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
        }
        d.json["extensions"] = {{"KHR_lights_punctual", {{"lights", lights}}}};
        d.json["extensionsUsed"] = {"KHR_lights_punctual"};
        const auto scene = folder / (fills ? "lamps.gltf" : "half.gltf");
        d.write(scene);
        for (const char* device : {"gpu", "cpu"}) {
            SCOPED_TRACE(device);
            const auto image = folder / (std::string(device) + ".pfm");
            const auto stats = folder / (std::string(device) + ".json");
            const auto result = test::runVkrt("--scene " + quoted(scene) + " --device " + device +
                                              " --integrator whitted --width 8 --spp 2 --out " +
                                              quoted(image) + " --stats " + quoted(stats));
            if (std::string(device) == "gpu" && result.exitCode != 0) {
                EXPECT_EQ(result.exitCode, 1) << result.output;
                const std::string expected =
                    scene.string() + (fills ? ": all 128 samples were left out"
                                            : ": every sample of 32 of the 8x8 pixels was left out");
                EXPECT_NE(result.output.find("vkrt: error: " + expected), std::string::npos) << result.output;
                EXPECT_FALSE(std::filesystem::exists(image));
                EXPECT_FALSE(std::filesystem::exists(stats));
                continue;
            }
            // The CPU, and a GPU without a loop budget: every sample kept, the quad lit.
            ASSERT_EQ(result.exitCode, 0) << result.output;
            std::ifstream file(stats);
            EXPECT_EQ(nlohmann::json::parse(file)["nonfinite_samples"], 0u);
            EXPECT_GT(readImage(image.string()).at(1, 4).x, 0.0f);
            std::filesystem::remove(image);
            std::filesystem::remove(stats);
        }
    }
}

// The shader is specialised to the scene: the Cornell box (area lights, flat Lambertian walls) compiles none
// of the other features, and `--shader-features all`, the diagnostic that compiles every one, gives a larger
// shader and the same image. The stats record which was asked, the SPIR-V's size and the times to make it.
TEST(Cli, ShaderIsSpecialisedUnlessEveryFeatureIsAsked) {
    const auto folder = test::temporaryFolder();
    auto render = [&](const std::string& features) {
        const auto stats = folder / (features + ".json");
        const auto result = test::runVkrt("--scene " + kCornell + " --quiet --width 16 --height 16 --spp 1" +
                                          " --shader-features " + features + " --out " +
                                          quoted(folder / (features + ".pfm")) + " --stats " + quoted(stats));
        EXPECT_EQ(result.exitCode, 0) << result.output;
        std::ifstream file(stats);
        return nlohmann::json::parse(file);
    };
    const nlohmann::json scene = render("scene"), all = render("all");
    EXPECT_EQ(scene["features"], nlohmann::json::array({"area_lights"}));
    for (const char* feature : {"textures", "transmission", "volumes", "absorption", "punctual_lights",
                                "spheres", "shapes", "motion_blur", "normal_maps", "alpha", "environment",
                                "rough_specular", "traced_lobes", "glossy_lobes", "rough_refraction"}) {
        EXPECT_NE(std::find(all["features"].begin(), all["features"].end(), feature), all["features"].end())
            << feature;
    }
    EXPECT_EQ(scene["shader"]["features"], "scene");
    EXPECT_EQ(all["shader"]["features"], "all");
    EXPECT_LT(scene["shader"]["spirv_bytes"].get<size_t>(), all["shader"]["spirv_bytes"].get<size_t>());
    for (const nlohmann::json* json : {&scene, &all}) {
        EXPECT_GE((*json)["shader"]["compile_ms"].get<double>(), 0.0);
        EXPECT_GT((*json)["shader"]["pipeline_ms"].get<double>(), 0.0);
    }
    const Image a = readImage((folder / "scene.pfm").string()), b = readImage((folder / "all.pfm").string());
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a.pixels[i][c], b.pixels[i][c], 1e-5f * (1.0f + b.pixels[i][c])) << "pixel " << i;
        }
    }
}

// The CSG scene's solids reach the stats and the shader: its eight objects (three CSG objects of 2, 2 and 3
// shapes, five single shapes) on both devices, and the GPU's variant has the shapes' code.
TEST(Cli, StatsCountTheScenesSolidsAndShapes) {
    const auto folder = test::temporaryFolder();
    for (const char* device : {"gpu", "cpu"}) {
        const auto stats = folder / (std::string(device) + ".json");
        const auto result = test::runVkrt("--scene " + quoted(test::sourceDir() / "scenes/csg.gltf") +
                                          " --device " + device + " --quiet --width 16 --spp 1 --out " +
                                          quoted(folder / "csg.png") + " --stats " + quoted(stats));
        ASSERT_EQ(result.exitCode, 0) << result.output;
        std::ifstream file(stats);
        const nlohmann::json json = nlohmann::json::parse(file);
        EXPECT_EQ(json["solids"], 8) << device;
        EXPECT_EQ(json["shapes"], 12) << device;
        EXPECT_EQ(json["spheres"], 0) << device;
        EXPECT_EQ(json["triangles"], 2) << device;
        if (std::string(device) == "gpu") {
            EXPECT_NE(std::find(json["features"].begin(), json["features"].end(), "shapes"),
                      json["features"].end());
        }
    }
}

}  // namespace vkrt
