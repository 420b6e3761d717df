#include "app/render_summary.h"

#include <sys/resource.h>

#include <cstdio>
#include <string>

#include "app/huge_page_heap.h"
#include "scene/shading_inputs.h"

namespace vkrt {
namespace {

// The most resident memory the process has had, in bytes.
uint64_t peakResidentBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<uint64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace

void describeRun(const Options& options, const Scene& scene, const RenderSettings& settings,
                 const Camera& camera, RunReport& report) {
    report.scene = options.scenePath;
    report.device = options.device == DeviceKind::Gpu ? "gpu" : "cpu";
    report.camera = camera.name;
    report.triangles = scene.triangles.size();
    report.spheres = scene.spheres.size();
    report.solids = scene.solids.size();
    report.shapes = scene.shapes.size();
    report.textureBytes = packedTextureBytes(scene);
    report.settings = settings;
    if (const EnvironmentMap& e = scene.environment; e.present()) {
        report.environment =
            RunReport::Environment{std::nullopt, e.path, e.width, e.height, e.rotationDegrees, e.strength};
        if (e.neutral) report.environment->uniformRadiance = glm::dvec3(e.radiance.front());
    }
}

void recordResult(const RenderResult& result, RunReport& report) {
    report.samplesRendered = static_cast<int>(result.fewestSamples);
    report.mostSamplesRendered = static_cast<int>(result.mostSamples);
    report.stopped = result.stopped;
    report.rays = result.rays;
}

void writeStats(FileBatch& batch, const Options& options, RunReport& report) {
    report.memory.hostPeakBytes = peakResidentBytes();
    report.memory.hostHugePageBytes = hugePageBytes();
    if (!options.statsPath.empty()) stageJson(batch, toJson(report), options.statsPath);
}

bool samplesLeftOutOfWholePixels(const RenderResult& result, const std::string& scenePath) {
    const char* why =
        "(not finite, beyond their pixel's sum, or past the device's loop budget: llvmpipe's is 65535 passes "
        "an "
        "invocation, and --device cpu has none); nothing written";
    if (result.mostSamples > 0 && result.samplesKept == 0) {
        std::fprintf(stderr, "vkrt: error: %s: all %llu samples were left out %s\n", scenePath.c_str(),
                     static_cast<unsigned long long>(result.rays.nonFiniteSamples), why);
        return true;
    }
    // Where every pixel had samples traced, one without any kept lost them all.
    if (result.fewestSamples > 0 && result.pixelsWithoutSamples > 0) {
        std::fprintf(stderr, "vkrt: error: %s: every sample of %llu of the %dx%d pixels was left out %s\n",
                     scenePath.c_str(), static_cast<unsigned long long>(result.pixelsWithoutSamples),
                     result.image.width, result.image.height, why);
        return true;
    }
    return false;
}

bool interruptedBeforeEveryPixel(const RenderResult& result) {
    if (result.stopped != StopReason::Requested || result.fewestSamples > 0) return false;
    std::fprintf(stderr, "vkrt: interrupted before every pixel had a sample; nothing written\n");
    return true;
}

void printRenderSummary(const Options& options, const RunReport& report, int ranks) {
    if (options.quiet) return;
    // What was written, how many samples and how fast; on how many ranks, or on which GPU.
    const double mrays = static_cast<double>(report.rays.total()) / (report.renderMs / 1000.0) / 1e6;
    const std::string spp =
        report.mostSamplesRendered > report.samplesRendered
            ? std::to_string(report.samplesRendered) + " to " + std::to_string(report.mostSamplesRendered)
            : std::to_string(report.samplesRendered);
    const std::string where = ranks > 1    ? " on " + std::to_string(ranks) + " ranks"
                              : report.gpu ? " on " + report.gpu->deviceName
                                           : std::string();
    std::fprintf(stderr, "vkrt: %swrote %s (%dx%d, %s spp) in %.0f ms, %.2f Mrays/s%s\n",
                 report.stopped == StopReason::Requested ? "interrupted: " : "", options.outputPath.c_str(),
                 report.settings.width, report.settings.height, spp.c_str(), report.renderMs, mrays,
                 where.c_str());
    // Samples left out of their pixels' averages: not finite in single precision (the image's, on either
    // device), a BVH walk or light loop cut short, or (on the GPU) radiance that would take a pixel's
    // single-precision sum beyond its range.
    if (report.rays.nonFiniteSamples > 0) {
        std::fprintf(stderr,
                     "vkrt: warning: %llu samples were not finite in single precision (or would overflow "
                     "their pixel's sum, or "
                     "ran past the device's loop budget: llvmpipe's is 65535 passes an invocation, and "
                     "--device cpu has none) and were left out\n",
                     static_cast<unsigned long long>(report.rays.nonFiniteSamples));
    }
    // Each rank's share.
    for (size_t i = 0; i < report.ranks.size(); ++i) {
        const RunReport::Rank& r = report.ranks[i];
        std::fprintf(stderr, "vkrt:   rank %zu: %s, %llu spp in %u batches, %.0f ms\n", i,
                     r.deviceName.c_str(), static_cast<unsigned long long>(r.samples), r.batches, r.renderMs);
    }
}

}  // namespace vkrt
