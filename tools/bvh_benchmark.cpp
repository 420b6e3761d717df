// BVH build benchmark: builds the binned SAH BVH over a procedural mesh or a glTF file's triangles several
// times and prints JSON with the median, minimum and maximum build time, node count, depth and SAH cost.
// When built with Embree, Embree builds the same triangles on the same number of threads in the same runs,
// interleaved with vkrt's builds, at each quality asked for, and the JSON gives vkrt / Embree from the
// medians of that run.
//
//   bvh_benchmark [--triangles N | --scene FILE.gltf] [--runs R] [--threads T] [--embree QUALITY...]
//   (--help lists every option with its range; a bad argument prints one line and exits 2)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <thread>

#include <sys/resource.h>

#include <nlohmann/json.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/triangle_bvh.h"
#include "command_line.h"
#include "common/elapsed_time.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#ifdef VKRT_HAVE_EMBREE
#include "embree_build_timer.h"
#endif

namespace {

using vkrt::millisecondsSince;

// CPU time used by every thread of this process so far, in milliseconds (Embree's workers included).
double processCpuMs() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto ms = [](const timeval& t) {
        return 1e3 * static_cast<double>(t.tv_sec) + 1e-3 * static_cast<double>(t.tv_usec);
    };
    return ms(usage.ru_utime) + ms(usage.ru_stime);
}

nlohmann::json summarize(const std::vector<double>& times) {
    std::vector<double> sorted = times;
    std::sort(sorted.begin(), sorted.end());
    const size_t n = sorted.size();
    const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    return {{"median", median}, {"min", sorted.front()}, {"max", sorted.back()}, {"all", times}};
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vkrt;
    size_t triangleTarget = 1'000'000;
    int runs = 5;
    int threads = 0;
    std::string scenePath;
    std::vector<std::string> embreeQualities = {"low", "medium", "high"};
    CLI::App app{"Times the binned SAH BVH build (and Embree's, on the same triangles) and prints JSON.",
                 "bvh_benchmark"};
    auto* triangleOption =
        app.add_option("--triangles", triangleTarget, "about this many triangles in a UV sphere")
            ->check(CLI::Range(size_t{1}, size_t{1'000'000'000}))
            ->capture_default_str();
    app.add_option("--runs", runs, "builds to time")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--threads", threads, "build threads, vkrt's and Embree's (0: one per core)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_option("--scene", scenePath, "the triangles of a glTF file instead of the sphere")
        ->check(CLI::ExistingFile)
        ->excludes(triangleOption);
    app.add_option("--embree", embreeQualities,
                   "Embree build qualities to time beside vkrt's (none: vkrt alone; ignored without Embree)")
        ->check(CLI::IsMember({"none", "low", "medium", "high"}))
        ->capture_default_str();
    if (const std::optional<int> exitCode = parseCommandLine(app, argc, argv)) return *exitCode;
    if (std::find(embreeQualities.begin(), embreeQualities.end(), "none") != embreeQualities.end()) {
        embreeQualities.clear();
    }

    std::vector<Triangle> triangles;
    std::string input;
    try {
        if (!scenePath.empty()) {
            triangles = loadGltf(scenePath).triangles;
            input = scenePath;
        } else {
            // A UV sphere with rings = segments / 2 has segments^2 triangles.
            const int segments =
                std::max(4, static_cast<int>(std::sqrt(static_cast<double>(triangleTarget))));
            triangles = makeUvSphere(glm::vec3(0.0f), 1.0f, segments / 2, segments);
            input = "uv-sphere";
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bvh_benchmark: error: %s\n", e.what());
        return 1;
    }

    BvhConfig config;
    config.threads = threads;
#ifdef VKRT_HAVE_EMBREE
    std::optional<EmbreeBuildTimer> embree;
    if (!embreeQualities.empty()) embree.emplace(triangles, threads);
#else
    embreeQualities.clear();
#endif
    // Each run: vkrt's bounds and build, then Embree at each quality, so that load changes hit all alike.
    std::vector<double> buildTimes, totalTimes, cpuTimes;
    std::map<std::string, std::vector<double>> embreeTimes, embreeCpuTimes;
    BvhStats stats;
    for (int run = 0; run < runs; ++run) {
        const double cpuStart = processCpuMs();
        const auto start = std::chrono::steady_clock::now();
        const HugePageVector<Aabb> bounds = triangleBounds(triangles, threads);
        const auto buildStart = std::chrono::steady_clock::now();
        const Bvh bvh = BinnedSahBuilder::build(bounds, config);
        buildTimes.push_back(millisecondsSince(buildStart));
        totalTimes.push_back(millisecondsSince(start));
        cpuTimes.push_back(processCpuMs() - cpuStart);
        if (run == 0) stats = measureBvh(bvh, config);
#ifdef VKRT_HAVE_EMBREE
        for (const std::string& quality : embreeQualities) {
            for (EmbreeBuildQuality q :
                 {EmbreeBuildQuality::Low, EmbreeBuildQuality::Medium, EmbreeBuildQuality::High}) {
                if (quality != qualityName(q)) continue;
                const double embreeCpuStart = processCpuMs();
                embreeTimes[quality].push_back(embree->build(q));
                embreeCpuTimes[quality].push_back(processCpuMs() - embreeCpuStart);
            }
        }
#endif
    }
    const nlohmann::json total = summarize(totalTimes);
    nlohmann::json report = {
        {"benchmark", "bvh_build"},
        {"input", input},
        {"triangles", triangles.size()},
        {"threads", threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())},
        {"runs", runs},
        // The builder from the triangles' bounds, as the renderers time it.
        {"build_ms", summarize(buildTimes)},
        // The bounds of every triangle and the build: what Embree's time covers.
        {"from_triangles_ms", total},
        // CPU time of all threads over the same span: less sensitive to a busy machine than wall time.
        {"from_triangles_cpu_ms", summarize(cpuTimes)},
        {"nodes", stats.nodes},
        {"leaves", stats.leaves},
        {"depth", stats.depth},
        {"sah_cost", stats.sahCost},
    };
#ifdef VKRT_HAVE_EMBREE
    if (!embreeQualities.empty()) {
        nlohmann::json entry = {{"version", embreeVersion()}};
        for (const auto& [quality, times] : embreeTimes) {
            const nlohmann::json cpu = summarize(embreeCpuTimes[quality]);
            entry[quality] = {{"build_ms", summarize(times)}, {"cpu_ms", cpu}};
            entry[quality]["vkrt_over_embree"] =
                total["median"].get<double>() / entry[quality]["build_ms"]["median"].get<double>();
            entry[quality]["vkrt_over_embree_cpu"] =
                summarize(cpuTimes)["median"].get<double>() / cpu["median"].get<double>();
        }
        report["embree"] = entry;
    }
#endif
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
}
