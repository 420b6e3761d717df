#include "app/rank_render.h"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/convergence_run.h"
#include "app/exit_codes.h"
#include "app/gpu_run.h"
#include "app/progress_bar.h"
#include "app/render_summary.h"
#include "app/shared_render.h"
#include "app/stop_signal.h"
#include "common/atomic_file.h"
#include "common/elapsed_time.h"
#include "cpu/reference_renderer.h"
#include "image/image_io.h"

namespace vkrt {
namespace {

// What makes a rank's image, one "name: value" line each (numbers to the last bit), so that ranks given
// different options are refused rather than mixed into one image; not how it is made (threads, device).
std::string renderIdentity(const Options& options, const RenderSetup& setup) {
    const RenderSettings& s = setup.settings;
    const Camera& c = setup.camera;
    std::ostringstream out;
    out << std::setprecision(17);
    const auto line = [&](const char* name, const auto&... values) {
        out << name << ":";
        ((out << " " << values), ...);
        out << "\n";
    };
    const auto vector = [](const glm::dvec3& v) {
        std::ostringstream text;
        text << std::setprecision(17) << v.x << "," << v.y << "," << v.z;
        return text.str();
    };
    const auto file = [](const std::string& path) {
        std::error_code error;
        const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, error);
        return error ? path : canonical.string();
    };
    line("scene", file(options.scenePath));
    line("size", std::to_string(s.width) + "x" + std::to_string(s.height));
    line("spp", s.samplesPerPixel);
    line("seed", s.seed);
    line("integrator", integratorName(s.integrator));
    line("max depth", s.maxDepth);
    line("ambient", vector(s.ambient));
    line("background", vector(s.background));
    line("min throughput", s.minThroughput);
    line("filter", static_cast<int>(s.pixelFilter));
    line("light samples", s.lightSamples);
    line("mis", s.multipleImportanceSampling);
    line("energy compensation", s.energyCompensation);
    line("camera", c.name, static_cast<int>(c.projection), vector(c.position), vector(c.forward),
         vector(c.up), c.yfov, c.xmag, c.ymag);
    line("aperture", c.aperture);
    line("focus distance", c.focusDistance);
    if (options.shutter)
        line("shutter", (*options.shutter)[0], (*options.shutter)[1]);
    else
        line("shutter", "the scene's");
    line("animation", options.animation.empty() ? std::string("the first") : options.animation);
    line("environment", options.environmentPath.empty() ? std::string("none") : file(options.environmentPath),
         options.environmentRotation, options.environmentStrength);
    return out.str();
}

// The first line in which two identities differ: "<that line>, rank 0 <its line>".
std::string firstDifference(const std::string& rank, const std::string& root) {
    std::istringstream a(rank), b(root);
    std::string lineA, lineB;
    while (std::getline(a, lineA)) {
        std::getline(b, lineB);
        if (lineA != lineB) return "with " + lineA + ", rank 0 with " + lineB;
    }
    return "another image";
}

}  // namespace

int renderShared(const MpiJob& job, const Options& options, const PreparedRender& prepared,
                 RunReport& report) {
    const Scene& scene = prepared.scene;
    const RenderSetup& setup = prepared.setup;
    const FlatBvh& flatBvh = prepared.bvh.flat;
    const VulkanContext* context = prepared.context.get();
    const RenderSettings& settings = setup.settings;
    const size_t pixels = static_cast<size_t>(settings.width) * settings.height;
    RunReport::Rank mine;
    mine.device = context ? "gpu" : "cpu";
    std::optional<RunReport::Gpu> gpu;

    // This rank's share of a render with `renderSettings` on its device; the renderer is made once for it.
    std::chrono::steady_clock::time_point renderStart;
    auto share = [&](const RenderSettings& renderSettings, const char* label, const StopCondition& stop,
                     const ShareOptions& shareOptions, bool forStats) {
        if (forStats) renderStart = std::chrono::steady_clock::now();  // before the renderer's set-up
        ProgressBar progress(label, !options.quiet);
        const auto onProgress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
        const uint32_t spp = static_cast<uint32_t>(renderSettings.samplesPerPixel);
        renderBegins();
        RankShare rankShare;
        if (context) {
            GpuRenderer renderer(*context, scene, flatBvh, setup.camera, renderSettings,
                                 gpuRenderOptions(options));
            rankShare = renderShare(
                job, spp,
                [&](uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums, const StopCondition& s) {
                    const RenderResult batch = renderer.renderSamples(first, end, sums, s);
                    throwOnValidationMessages(*context);  // here, while the other ranks can still be ended
                    return batch;
                },
                stop, onProgress, shareOptions);
            if (forStats) {
                gpu = gpuReportOf(options, *context, renderer);
                recordDeviceMemory(renderer, report);
                mine.deviceName = gpu->deviceName;
            }
        } else {
            const ReferenceRenderer renderer(scene, flatBvh, setup.camera, renderSettings);
            rankShare = renderShare(
                job, spp,
                [&](uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums, const StopCondition& s) {
                    return renderer.renderSamples(first, end, sums, s);
                },
                stop, onProgress, shareOptions);
            mine.deviceName = "cpu reference";
        }
        progress.finish();
        // The others are gone (a rank failed and the launcher is ending the job): write nothing, wait for
        // nothing.
        if (rankShare.abandoned) std::_Exit(stoppedExitCode());
        return rankShare;
    };
    ShareOptions shareOptions;
    shareOptions.stopRequested = &stopRequested();
    shareOptions.pixels = pixels;

    // Every rank must render the same image (on whatever device): a different size would not even add up, and
    // different settings would be mixed into one image.
    const std::vector<std::string> renders = job.gatherToRoot(renderIdentity(options, setup));
    for (size_t rank = 1; rank < renders.size(); ++rank) {
        if (renders[rank] != renders[0]) {
            throw UsageError("rank " + std::to_string(rank) + " renders " +
                             firstDifference(renders[rank], renders[0]) +
                             ": every rank needs the same scene and render options");
        }
    }
    const bool anyGpu = job.anyRank(context != nullptr), anyCpu = job.anyRank(context == nullptr);

    // Error against run time (rank 0): a reference from a file, or a render shared as the render is, with
    // another seed and 16 times the samples. Rank 0's options decide for every rank: the others' report
    // options are not theirs to use (an MPMD job may give them other ones), and all must render the
    // reference.
    std::optional<ConvergenceReport> convergence;
    if (job.fromRoot(!options.referencePath.empty())) {
        if (job.rank() == 0) convergence.emplace(referenceFromFile(options, settings));
    } else if (job.fromRoot(!options.reportPath.empty())) {
        const RenderSettings referenceSettings = referenceRenderSettings(settings);
        const std::string source = announceRenderedReference(options, referenceSettings,
                                                             anyGpu && anyCpu ? "gpu and cpu"
                                                             : anyGpu         ? "gpu"
                                                                              : "cpu",
                                                             job.size());
        // The reference renders all its samples (no time limit); an interrupt leaves nothing to keep.
        RankShare reference =
            share(referenceSettings, "reference", StopCondition(&stopRequested(), 0.0), shareOptions, false);
        std::vector<RunReport::Rank> unused;
        const RenderResult referenceImage =
            combineShares(job, reference, mine, settings.width, settings.height, unused);
        if (job.rank() == 0) {
            if (referenceImage.stopped == StopReason::Requested) throw InterruptedBeforeRender{};
            convergence.emplace(referenceImage.image, source);
        }
    }
    if (convergence) {
        shareOptions.checkpoint = [&](uint32_t samples, double renderMs,
                                      const std::vector<glm::dvec4>& sums) {
            // No one GPU time belongs to a checkpoint of several ranks: left empty (it read 0).
            convergence->add(samples, renderMs, kNoGpuTime, averageOf(sums, settings.width, settings.height));
        };
    }
    // Every rank's phases end where rank 0's do: its --report-every-ms, whatever the others were given.
    shareOptions.checkpointEveryMs = job.fromRoot(options.reportEveryMs);

    // The render itself, and every rank's share of it summed on rank 0.
    shareOptions.setupStarted = std::chrono::steady_clock::now();
    RankShare rendered = share(settings, context ? "gpu" : "cpu",
                               StopCondition(&stopRequested(), options.timeLimitSeconds), shareOptions, true);
    mine.samples = rendered.fewest;
    mine.samplesMax = rendered.most;
    mine.batches = rendered.batches;
    mine.rays = rendered.rays;
    mine.renderMs = rendered.renderMs;
    const RenderResult result =
        combineShares(job, rendered, mine, settings.width, settings.height, report.ranks);
    if (job.rank() != 0) return 0;
    // The render took from rank 0's renderer set-up (the GPU's pipeline among it, as one process counts it;
    // the ranks' set-ups run side by side) until the last rank's batch ended (the sums were reduced after
    // it).
    report.renderMs = millisecondsSince(renderStart);

    // Rank 0: the image and the stats, as one process writes them.
    if (samplesLeftOutOfWholePixels(result, options.scenePath) || interruptedBeforeEveryPixel(result)) {
        return result.stopped == StopReason::Requested ? stoppedExitCode() : kExitRuntimeFailure;
    }
    // All of them or none (one_process_render.cpp).
    FileBatch outputs;
    stageImage(outputs, result.image, options.outputPath, options.exposure, options.toneMap);
    describeRun(options, scene, settings, setup.camera, report);
    for (const RunReport::Rank& rank : report.ranks) {
        if (rank.device != report.ranks.front().device) report.device = "mixed";
    }
    report.gpu = gpu;
    recordResult(result, report);
    writeStats(outputs, options, report);
    if (convergence) writeConvergence(outputs, options, *convergence, report, settings, job.size());
    outputs.commit();
    printRenderSummary(options, report, job.size());
    if (!options.quiet && result.fewestSamples == 0) {
        std::fprintf(stderr,
                     "vkrt: warning: the render stopped before every pixel had a sample; those are black\n");
    }
    // An interrupt on another rank (mpirun forwards SIGTERM) ends the job as one on this one would.
    if (result.stopped == StopReason::Requested) return stoppedExitCode();
    return 0;
}

}  // namespace vkrt
