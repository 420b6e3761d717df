// Every tool checks its arguments: --help prints the options and exits 0; a bad argument (unknown flag,
// value out of range, not a number, missing value, missing file, options that exclude each other) prints
// exactly one line naming the tool and the problem, and exits 2 before any work starts.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

struct BadArguments {
    const char* tool;       // the binary
    const char* name;       // what it calls itself in its error line
    std::string arguments;  // already quoted where needed
    const char* mentions;   // a word the error line must contain
};

// 'TOOL' ARGUMENTS, built by appending (GCC 12 warns falsely on chained operator+ here, -Wrestrict).
std::string commandLine(const std::string& tool, const std::string& arguments) {
    std::string line = "'";
    line.append(tool).append("' ").append(arguments);
    return line;
}

std::string quotedCornell() {
    std::string quoted = "'";
    quoted.append((test::sourceDir() / "scenes/cornell.gltf").string()).append("'");
    return quoted;
}

std::vector<BadArguments> badArguments() {
    return {
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--runs 0", "--runs"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--runs abc", "--runs"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--triangles -5", "--triangles"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--threads 100000", "--threads"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--runs", "--runs"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--bogus 3", "--bogus"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--scene /nonexistent/scene.gltf", "--scene"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--scene " + quotedCornell() + " --triangles 10", "excludes"},
        {VKRT_BVH_BENCHMARK, "bvh_benchmark", "--embree best", "--embree"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--width 0", "--width"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--height 99999", "--height"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--runs 2.5", "--runs"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--device-index -2", "--device-index"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--triangles 99999999999999999999999", "--triangles"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "--scene " + quotedCornell() + " --triangles 10", "excludes"},
        {VKRT_RAY_BENCHMARK, "ray_benchmark", "positional", "positional"},
        {VKRT_STABILITY_REPORT, "stability_report", "--size 0", "--size"},
        {VKRT_STABILITY_REPORT, "stability_report", "--spp many", "--spp"},
        {VKRT_STABILITY_REPORT, "stability_report", "--long-samples -1", "--long-samples"},
        {VKRT_STABILITY_REPORT, "stability_report", "--dump", "--dump"},
        {VKRT_STABILITY_REPORT, "stability_report", "--json --dump out extra", "extra"},
        {VKRT_PACK_SCENE, "pack_scene", "", "input"},
        {VKRT_PACK_SCENE, "pack_scene", "--draco /nonexistent/scene.gltf out.glb", "input"},
        {VKRT_PACK_SCENE, "pack_scene", "--draco --webp " + quotedCornell() + " out.glb", "excludes"},
        {VKRT_PACK_SCENE, "pack_scene", quotedCornell() + " out.glb", "--draco or --webp"},
    };
}

TEST(ToolsCli, BadArgumentsExitTwoWithOneLine) {
    for (const BadArguments& c : badArguments()) {
        SCOPED_TRACE(std::string(c.name) + " " + c.arguments);
        const test::CommandResult result = test::runCommand(commandLine(c.tool, c.arguments));
        EXPECT_EQ(result.exitCode, 2) << result.output;
        ASSERT_FALSE(result.output.empty());
        EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << "one line, got:\n" << result.output;
        EXPECT_EQ(result.output.rfind(std::string(c.name) + ": error: ", 0), 0u) << result.output;
        EXPECT_NE(result.output.find(c.mentions), std::string::npos) << result.output;
    }
}

TEST(ToolsCli, HelpListsTheOptionsAndExitsZero) {
    const std::vector<std::pair<const char*, std::vector<const char*>>> tools = {
        {VKRT_BVH_BENCHMARK, {"--triangles", "--runs", "--threads", "--scene", "--embree"}},
        {VKRT_RAY_BENCHMARK, {"--scene", "--triangles", "--width", "--height", "--runs", "--device-index"}},
        {VKRT_STABILITY_REPORT, {"--size", "--spp", "--long-samples", "--json", "--dump"}},
        {VKRT_PACK_SCENE, {"--draco", "--webp", "input", "output"}},
    };
    for (const auto& [tool, options] : tools) {
        SCOPED_TRACE(tool);
        const test::CommandResult result = test::runCommand(commandLine(tool, "--help"));
        EXPECT_EQ(result.exitCode, 0) << result.output;
        for (const char* option : options) {
            EXPECT_NE(result.output.find(option), std::string::npos) << option << " in\n" << result.output;
        }
    }
}

// ray_benchmark's figures where they are thin: with two rays of a kind the median is their mean (it was the
// larger), and a kind with no rays (no camera ray hit anything) is reported as such, not as rates of 0/0.
TEST(ToolsCli, RayBenchmarkReportsFewAndNoRays) {
    const test::CommandResult two = test::runCommand(
        commandLine(VKRT_RAY_BENCHMARK, "--triangles 1000 --width 2 --height 1 --runs 1 --count-iterations"));
    ASSERT_EQ(two.exitCode, 0) << two.output;
    const nlohmann::json report = nlohmann::json::parse(two.output);
    bool unequal = false;  // some kind's two rays took different numbers of passes (else any middle would do)
    for (const auto& [kind, k] : report["kinds"].items()) {
        if (k["rays"].get<int>() != 2) continue;
        const nlohmann::json& passes = k["loop_iterations"];
        unequal = unequal || passes["max"].get<double>() != passes["mean"].get<double>();
        EXPECT_EQ(passes["median"].get<double>(), passes["mean"].get<double>()) << kind;
    }
    EXPECT_TRUE(unequal) << two.output;

    // One triangle behind the file's camera, which looks down -Z from the origin.
    const auto file = test::temporaryFolder() / "away.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAKBAAACAPwAAAAAAAKBAAAAAAAAAgD8AAKBA",
                     "byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 5], "max": [1, 1, 5]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
        "nodes": [{"mesh": 0}, {"camera": 0}]
    })");
    const test::CommandResult away = test::runCommand(
        commandLine(VKRT_RAY_BENCHMARK, "--scene '" + file.string() + "' --width 4 --height 4 --runs 1"));
    ASSERT_EQ(away.exitCode, 0) << away.output;
    const nlohmann::json missed = nlohmann::json::parse(away.output);
    EXPECT_EQ(missed["kinds"]["camera"]["rays"], 16);
    for (const char* kind : {"shadow", "diffuse"}) {
        EXPECT_EQ(missed["kinds"][kind], nlohmann::json({{"rays", 0}}))
            << kind << ": " << missed["kinds"][kind];
    }
}

}  // namespace
}  // namespace vkrt
