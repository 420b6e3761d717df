// BVH build benchmark: builds the binned SAH BVH over a procedural mesh several times and prints JSON with
// the median, minimum and maximum build time, node count, depth and SAH cost.
//
//   bvh_benchmark [--triangles N] [--runs R] [--threads T] [--scene FILE.gltf]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bvh/binned_sah_builder.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"

int main(int argc, char** argv) {
    using namespace vkrt;
    size_t triangleTarget = 1'000'000;
    int runs = 5;
    int threads = 0;
    std::string scenePath;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i];
        if (flag == "--triangles")
            triangleTarget = std::stoull(argv[i + 1]);
        else if (flag == "--runs")
            runs = std::max(1, std::stoi(argv[i + 1]));
        else if (flag == "--threads")
            threads = std::stoi(argv[i + 1]);
        else if (flag == "--scene")
            scenePath = argv[i + 1];
        else {
            std::fprintf(stderr,
                         "usage: bvh_benchmark [--triangles N] [--runs R] [--threads T] [--scene FILE]\n");
            return 2;
        }
    }
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
