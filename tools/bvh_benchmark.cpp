// BVH build benchmark: builds the binned SAH BVH over a procedural mesh several times and prints JSON with
// the median, minimum and maximum build time, node count, depth and SAH cost.
//
//   bvh_benchmark [--triangles N | --scene FILE.gltf] [--runs R] [--threads T]
//   (--help lists every option with its range; a bad argument prints one line and exits 2)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bvh/binned_sah_builder.h"
#include "command_line.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"

int main(int argc, char** argv) {
    using namespace vkrt;
    size_t triangleTarget = 1'000'000;
    int runs = 5;
    int threads = 0;
    std::string scenePath;
    CLI::App app{"Times the binned SAH BVH build and prints JSON.", "bvh_benchmark"};
    auto* triangleOption =
        app.add_option("--triangles", triangleTarget, "about this many triangles in a UV sphere")
            ->check(CLI::Range(size_t{1}, size_t{1'000'000'000}))
            ->capture_default_str();
    app.add_option("--runs", runs, "builds to time")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--threads", threads, "build threads (0: one per core)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_option("--scene", scenePath, "the triangles of a glTF file instead of the sphere")
        ->check(CLI::ExistingFile)
        ->excludes(triangleOption);
    if (const std::optional<int> exitCode = parseCommandLine(app, argc, argv)) return *exitCode;

    std::vector<Triangle> triangles;
    std::string input;
    if (!scenePath.empty()) {
        triangles = loadGltf(scenePath).triangles;
        input = scenePath;
    } else {
        // A UV sphere with rings = segments / 2 has segments^2 triangles.
        const int segments = std::max(4, static_cast<int>(std::sqrt(static_cast<double>(triangleTarget))));
        triangles = makeUvSphere(glm::vec3(0.0f), 1.0f, segments / 2, segments);
        input = "uv-sphere";
    }
    std::vector<Aabb> bounds(triangles.size());
    for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = triangles[i].bounds();

    BvhConfig config;
    config.threads = threads;
    std::vector<double> times;
    BvhStats stats;
    for (int run = 0; run < runs; ++run) {
        const auto start = std::chrono::steady_clock::now();
        const Bvh bvh = BinnedSahBuilder::build(bounds, config);
        times.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        if (run == 0) stats = measureBvh(bvh, config);
    }
    std::vector<double> sorted = times;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.size() % 2
                              ? sorted[sorted.size() / 2]
                              : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
    const nlohmann::json report = {
        {"benchmark", "bvh_build"},
        {"input", input},
        {"triangles", triangles.size()},
        {"threads", threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())},
        {"runs", runs},
        {"build_ms", {{"median", median}, {"min", sorted.front()}, {"max", sorted.back()}, {"all", times}}},
        {"nodes", stats.nodes},
        {"leaves", stats.leaves},
        {"depth", stats.depth},
        {"sah_cost", stats.sahCost},
    };
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
}
