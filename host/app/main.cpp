// vkrt: renders a glTF 2.0 scene to an image file.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <new>
#include <optional>
#include <string>

#include "app/convergence_report.h"
#include "app/host_memory.h"
#include "app/mpi_job.h"
#include "app/options.h"
#include "app/path_checks.h"
#include "app/progress_bar.h"
#include "app/render_policy.h"
#include "app/render_stats.h"
#include "app/shared_render.h"
#include "bvh/triangle_bvh.h"
#include "common/atomic_file.h"
#include "cpu/reference_renderer.h"
#include "gpu/gpu_renderer.h"
#include "gpu/vulkan_check.h"
#include "gpu/vulkan_context.h"
#include "image/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

constexpr int kExitRuntimeFailure = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitSignalBase = 128;  // ended by signal N: exit 128 + N, as shells report it

// SIGINT and SIGTERM: the first ends the render after the dispatch or pixel in flight, and the samples done
// are written as usual; a second ends the process at once.
std::atomic<bool> gStopRequested{false};
volatile std::sig_atomic_t gSignal = 0;
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void onStopSignal(int signal) {
    if (gSignal != 0) {
        if (gTemporaryFileBeingWritten[0] != '\0') unlink(gTemporaryFileBeingWritten);
        std::signal(signal, SIG_DFL);
        std::raise(signal);
        return;
    }
    gSignal = signal;
    gStopRequested.store(true);
}

// Interrupted before the render itself began (while making the reference of --report): nothing to keep.
struct InterruptedBeforeRender {};
// A reference made for a report without --reference has this many times the samples of the render.
constexpr int kReferenceSampleFactor = 16;

// The --environment map, decoded and checked; a file that cannot be used is bad input (exit code 2).
EnvironmentMap loadEnvironment(const Options& options) {
    Image image;
    try {
        image = readRadianceImage(options.environmentPath);
    } catch (const ImageError& e) {
        throw UsageError(std::string("--environment: ") + e.what());
    }
    return makeEnvironmentMap(options.environmentPath, image.width, image.height, std::move(image.pixels),
                              options.environmentRotation, options.environmentStrength);
}

// The most resident memory the process has had, in bytes.
uint64_t peakResidentBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<uint64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Estimates the host memory the render will take and refuses it (MemoryError) when it does not fit;
// records the estimate and what was available.
void checkHostMemoryFor(const Options& options, const Scene& scene, const RenderSettings& settings,
                        const VulkanContext* context, RunReport::Memory& memory) {
    HostMemoryInputs inputs;
    inputs.triangles = scene.triangles.size();
    inputs.textureBytes = packedTextureBytes(scene);
    inputs.width = settings.width;
    inputs.height = settings.height;
    inputs.gpu = context != nullptr;
    inputs.deviceInHostMemory = context && context->description().type == "CPU";
    if (inputs.deviceInHostMemory) {
        inputs.deviceBudgetBytes = context->memoryBudget().bytes;
        if (options.maxDeviceMemoryBytes > 0)
            inputs.deviceBudgetBytes = std::min(inputs.deviceBudgetBytes, options.maxDeviceMemoryBytes);
    }
    inputs.report = !options.reportPath.empty() || !options.referencePath.empty();
    inputs.outputPath = options.outputPath;
    const MemoryNeed need = estimateHostMemory(inputs);
    HostMemory available = availableHostMemory();
    if (options.maxHostMemoryBytes > 0 && options.maxHostMemoryBytes < available.bytes)
        available = HostMemory{options.maxHostMemoryBytes, "--max-memory"};
    checkHostMemory(need, available);
    memory.hostEstimateBytes = need.total();
    memory.hostAvailableBytes = available.bytes;
}

// What the stats say of the scene and the settings, whoever rendered it.
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
        report.environment = RunReport::Environment{e.path, e.width, e.height, e.rotationDegrees, e.strength};
    }
}

// The GPU renderer's options from the command line and the environment.
GpuRenderOptions gpuRenderOptions(const Options& options) {
    GpuRenderOptions gpuOptions;
    gpuOptions.allFeatures = options.allShaderFeatures;
    gpuOptions.maxDeviceMemoryBytes = options.maxDeviceMemoryBytes;
    // Testing aid: VKRT_SIMULATE_DEVICE_LOSS=N loses the device at the N-th dispatch.
    if (const char* loss = std::getenv("VKRT_SIMULATE_DEVICE_LOSS"))
        gpuOptions.simulateDeviceLossAtDispatch = static_cast<uint32_t>(std::strtoul(loss, nullptr, 10));
    return gpuOptions;
}

// The GPU tracer's figures for the stats.
RunReport::Gpu gpuReportOf(const Options& options, const VulkanContext& context,
                           const GpuRenderer& renderer) {
    const GpuRenderReport& g = renderer.report();
    RunReport::Gpu gpu;
    gpu.deviceName = context.description().name;
    gpu.deviceType = context.description().type;
    gpu.driver = context.description().driver;
    gpu.gpuMs = g.gpuMs;
    gpu.compileMs = g.compileMs;
    gpu.pipelineMs = g.pipelineMs;
    gpu.shaderFromCache = g.shaderFromCache;
    gpu.allFeatures = options.allShaderFeatures;
    gpu.spirvBytes = renderer.spirv().size() * sizeof(uint32_t);
    gpu.shaderKey = g.shaderKey;
    gpu.features = renderer.features().names();
    gpu.deviceMemoryBytes = g.deviceMemoryBytes;
    gpu.dispatches = g.dispatches;
    gpu.longestDispatchMs = g.longestDispatchMs;
    gpu.boundGeometry = g.boundGeometry;
    return gpu;
}

void throwOnValidationMessages(const VulkanContext& context) {
    if (context.validationMessages() > 0)
        throw GpuError(std::to_string(context.validationMessages()) + " validation message(s), see above");
}

// The --reference image, checked against the render's size.
ConvergenceReport referenceFromFile(const Options& options, const RenderSettings& settings) {
    Image reference;
    try {
        reference = readImage(options.referencePath);
    } catch (const ImageError& e) {
        throw UsageError(std::string("--reference: ") + e.what());
    }
    if (reference.width != settings.width || reference.height != settings.height) {
        throw UsageError("--reference: " + options.referencePath + " is " + std::to_string(reference.width) +
                         "x" + std::to_string(reference.height) + ", the render " +
                         std::to_string(settings.width) + "x" + std::to_string(settings.height));
    }
    return ConvergenceReport(std::move(reference), "file " + options.referencePath);
}

// What --report made of the render: the error at each checkpoint, written as the report and summed up in one
// line.
void writeConvergence(const Options& options, const ConvergenceReport& convergence, const RunReport& report,
                      const RenderSettings& settings, int ranks) {
    if (!options.reportPath.empty()) {
        nlohmann::json context = {
            {"scene", options.scenePath},
            {"device", report.device},
            {"device_name", report.gpu ? report.gpu->deviceName : std::string("cpu reference")},
            {"width", settings.width},
            {"height", settings.height},
            {"spp", report.samplesRendered},
            {"seed", settings.seed}};
        if (ranks > 1) context["ranks"] = ranks;
        convergence.write(options.reportPath, context);
    }
    if (!options.quiet && !convergence.points().empty()) {
        const ConvergencePoint& last = convergence.points().back();
        std::fprintf(
            stderr,
            "vkrt: error against the reference: RMSE %.4g, relMSE %.4g, %.2f%% of pixels off by >1%%\n",
            last.rmse, last.relMse, 100.0 * last.fractionOff);
    }
}

// Under mpirun: this rank's share of the render (shared_render.h); rank 0 sums the shares and writes the
// image and the stats. Every rank comes here with its scene, BVH and device ready.
int renderShared(const MpiJob& job, const Options& options, const Scene& scene, const RenderSetup& setup,
                 const FlatBvh& flatBvh, const VulkanContext* context, RunReport& report) {
    const RenderSettings& settings = setup.settings;
    const size_t pixels = static_cast<size_t>(settings.width) * settings.height;
    RunReport::Rank mine;
    mine.device = context ? "gpu" : "cpu";
    std::optional<RunReport::Gpu> gpu;

    // This rank's share of a render with `renderSettings` on its device; the renderer is made once for it.
    auto share = [&](const RenderSettings& renderSettings, const char* label, const StopCondition& stop,
                     const ShareOptions& shareOptions, bool forStats) {
        ProgressBar progress(label, !options.quiet);
        const auto onProgress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
        const uint32_t spp = static_cast<uint32_t>(renderSettings.samplesPerPixel);
        RankShare rankShare;
        if (context) {
            GpuRenderer renderer(*context, scene, flatBvh, setup.camera, renderSettings, gpuRenderOptions(options));
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
        if (rankShare.abandoned) std::_Exit(kExitSignalBase + (gSignal != 0 ? gSignal : SIGTERM));
        return rankShare;
    };
    ShareOptions shareOptions;
    shareOptions.stopRequested = &gStopRequested;
    shareOptions.pixels = pixels;

    // Every rank must render the same image (on whatever device): a different size would not even add up.
    const std::string renderOf =
        options.scenePath + ", " + std::to_string(settings.width) + "x" + std::to_string(settings.height) + ", " +
        std::to_string(settings.samplesPerPixel) + " spp, seed " + std::to_string(settings.seed) + ", " +
        integratorName(settings.integrator) + " depth " + std::to_string(settings.maxDepth) + ", camera " +
        setup.camera.name;
    const std::vector<std::string> renders = job.gatherToRoot(renderOf);
    for (size_t rank = 1; rank < renders.size(); ++rank) {
        if (renders[rank] != renders[0]) {
            throw UsageError("rank " + std::to_string(rank) + " renders " + renders[rank] + ", rank 0 " +
                             renders[0] + ": every rank needs the same scene and render options");
        }
    }

    // Error against run time (rank 0): a reference from a file, or a render shared as the render is, with
    // another seed and 16 times the samples.
    std::optional<ConvergenceReport> convergence;
    if (!options.referencePath.empty()) {
        if (job.rank() == 0) convergence.emplace(referenceFromFile(options, settings));
    } else if (!options.reportPath.empty()) {
        RenderSettings referenceSettings = settings;
        referenceSettings.samplesPerPixel = settings.samplesPerPixel * kReferenceSampleFactor;
        referenceSettings.seed = settings.seed + 1;
        const std::string source = std::string(context ? "gpu" : "cpu") + " render made by this run on " +
                                   std::to_string(job.size()) + " ranks, " +
                                   std::to_string(referenceSettings.samplesPerPixel) + " spp, seed " +
                                   std::to_string(referenceSettings.seed);
        if (!options.quiet) std::fprintf(stderr, "vkrt: reference: %s\n", source.c_str());
        // The reference renders all its samples (no time limit); an interrupt leaves nothing to keep.
        RankShare reference =
            share(referenceSettings, "reference", StopCondition(&gStopRequested, 0.0), shareOptions, false);
        std::vector<RunReport::Rank> unused;
        const RenderResult referenceImage =
            combineShares(job, reference, mine, settings.width, settings.height, unused);
        if (job.rank() == 0) {
            if (referenceImage.stopped == StopReason::Requested) throw InterruptedBeforeRender{};
            convergence.emplace(referenceImage.image, source);
        }
    }
    if (convergence) {
        shareOptions.checkpoint = [&](uint32_t samples, double renderMs, const std::vector<glm::dvec4>& sums) {
            convergence->add(samples, renderMs, 0.0, averageOf(sums, settings.width, settings.height));
        };
    }
    shareOptions.checkpointEveryMs = options.reportEveryMs;  // every rank's phases end where rank 0's do

    RankShare rendered = share(settings, context ? "gpu" : "cpu",
                               StopCondition(&gStopRequested, options.timeLimitSeconds), shareOptions, true);
    mine.samples = rendered.fewest;
    mine.samplesMax = rendered.most;
    mine.batches = rendered.batches;
    mine.rays = rendered.rays;
    mine.renderMs = rendered.renderMs;
    const RenderResult result = combineShares(job, rendered, mine, settings.width, settings.height, report.ranks);
    if (job.rank() != 0) return 0;
    // The render took until the last rank's batch ended (the sums were reduced after it).
    report.renderMs = millisecondsSince(rendered.started);

    // Rank 0: the image and the stats, as one process writes them.
    writeImage(result.image, options.outputPath, options.exposure, options.toneMap);
    describeRun(options, scene, settings, setup.camera, report);
    for (const RunReport::Rank& rank : report.ranks) {
        if (rank.device != report.ranks.front().device) report.device = "mixed";
    }
    report.gpu = gpu;
    report.samplesRendered = static_cast<int>(result.fewestSamples);
    report.mostSamplesRendered = static_cast<int>(result.mostSamples);
    report.stopped = result.stopped;
    report.rays = result.rays;
    report.memory.hostPeakBytes = peakResidentBytes();
    if (!options.statsPath.empty()) writeJson(toJson(report), options.statsPath);
    if (convergence) writeConvergence(options, *convergence, report, settings, job.size());
    if (!options.quiet) {
        const double mrays = static_cast<double>(result.rays.total()) / (report.renderMs / 1000.0) / 1e6;
        const std::string spp =
            report.mostSamplesRendered > report.samplesRendered
                ? std::to_string(report.samplesRendered) + " to " + std::to_string(report.mostSamplesRendered)
                : std::to_string(report.samplesRendered);
        std::fprintf(stderr, "vkrt: %swrote %s (%dx%d, %s spp) in %.0f ms, %.2f Mrays/s on %d ranks\n",
                     result.stopped == StopReason::Requested ? "interrupted: " : "",
                     options.outputPath.c_str(), settings.width, settings.height, spp.c_str(),
                     report.renderMs, mrays, job.size());
        for (size_t i = 0; i < report.ranks.size(); ++i) {
            const RunReport::Rank& r = report.ranks[i];
            std::fprintf(stderr, "vkrt:   rank %zu: %s, %llu spp in %u batches, %.0f ms\n", i,
                         r.deviceName.c_str(), static_cast<unsigned long long>(r.samples), r.batches,
                         r.renderMs);
        }
    }
    // An interrupt on another rank (mpirun forwards SIGTERM) ends the job as one on this one would.
    if (result.stopped == StopReason::Requested) return kExitSignalBase + (gSignal != 0 ? gSignal : SIGTERM);
    return 0;
}

int run(Options options, const MpiJob& job) {
    // One image, one stats file and one report, from rank 0, which alone checks where they go; the others say
    // only what goes wrong.
    Options checked = options;
    if (job.rank() != 0) {
        options.quiet = true;
        checked.outputPath.clear();
        checked.statsPath.clear();
        checked.reportPath.clear();
    }
    checkPaths(checked);
    const auto loadStart = std::chrono::steady_clock::now();
    LoadOptions loadOptions;
    loadOptions.shutter = options.shutter;
    Scene scene = loadGltf(options.scenePath, loadOptions);
    if (!options.environmentPath.empty()) scene.environment = loadEnvironment(options);
    addNeutralEnvironment(options.request, scene);
    RunReport report;
    report.loadMs = millisecondsSince(loadStart);
    if (!options.quiet) {
        for (const std::string& warning : scene.warnings) {
            std::fprintf(stderr, "vkrt: warning: %s: %s\n", options.scenePath.c_str(), warning.c_str());
        }
    }

    // Settings and camera from what was asked and what the scene holds.
    const RenderSetup setup = resolveRender(options.request, scene);
    const RenderSettings& settings = setup.settings;
    const Camera& camera = setup.camera;
    if (!options.quiet) {
        for (const std::string& warning : setup.warnings) {
            std::fprintf(stderr, "vkrt: warning: %s: %s\n", options.scenePath.c_str(), warning.c_str());
        }
    }

    // The Vulkan device, when rendering on the GPU. VKRT_VALIDATE=1 turns validation on without changing
    // the command line (the test suite uses it).
    std::unique_ptr<VulkanContext> context;
    if (options.device == DeviceKind::Gpu) {
        ContextOptions contextOptions;
        const char* validateEnv = std::getenv("VKRT_VALIDATE");
        contextOptions.validation = options.validate || (validateEnv && std::string(validateEnv) == "1");
        contextOptions.deviceIndex = options.deviceIndex;
        contextOptions.localRank = job.localRank();
        context = std::make_unique<VulkanContext>(contextOptions);
    }

    // Host memory, before any is spent on the render (the device's is planned by the GPU renderer).
    checkHostMemoryFor(options, scene, settings, context.get(), report.memory);

    // Acceleration structure.
    const TriangleBvh triangleBvh = buildSceneBvh(scene);
    const FlatBvh& flatBvh = triangleBvh.flat;
    report.bvh = triangleBvh.stats;
    if (job.shared()) return renderShared(job, options, scene, setup, flatBvh, context.get(), report);

    // One render on the chosen device; fills `runReport` when given.
    auto render = [&](const RenderSettings& renderSettings, const char* label,
                      const CheckpointCallback& checkpoint, RunReport* runReport) {
        ProgressBar progress(label, !options.quiet);
        const auto onProgress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
        const auto renderStart = std::chrono::steady_clock::now();
        // The time limit is the render's own; the reference of --report renders all its samples.
        const StopCondition stop(&gStopRequested, runReport ? options.timeLimitSeconds : 0.0);
        RenderResult rendered;
        if (context) {
            GpuRenderer renderer(*context, scene, flatBvh, camera, renderSettings, gpuRenderOptions(options));
            rendered = renderer.render(onProgress, checkpoint, options.reportEveryMs, stop);
            // The reference of --report is all or nothing.
            if (!runReport && rendered.stopped == StopReason::DeviceLost)
                throw GpuError(renderer.report().deviceLost + " while rendering the reference for --report");
            if (runReport) {
                const GpuRenderReport& g = renderer.report();
                runReport->memory.deviceEstimateBytes = g.memory.need.total();
                runReport->memory.deviceBudgetBytes = g.memory.budgetBytes;
                runReport->memory.tiles = g.memory.tiles;
                runReport->memory.tileRows = g.memory.tileRows;
                runReport->memory.hostCopies = g.hostCopies;
                runReport->deviceLost = g.deviceLost;
                runReport->gpu = gpuReportOf(options, *context, renderer);
            }
            throwOnValidationMessages(*context);
        } else {
            const ReferenceRenderer renderer(scene, flatBvh, camera, renderSettings);
            rendered = renderer.render(onProgress, checkpoint, options.reportEveryMs, stop);
        }
        if (runReport) {
            runReport->renderMs = millisecondsSince(renderStart);
            runReport->samplesRendered = static_cast<int>(rendered.fewestSamples);
            runReport->mostSamplesRendered = static_cast<int>(rendered.mostSamples);
            runReport->stopped = rendered.stopped;
        }
        progress.finish();
        if (!runReport && rendered.stopped == StopReason::Requested) throw InterruptedBeforeRender{};
        return rendered;
    };

    // Error against run time: a reference from a file, or a long render made here with another seed.
    std::optional<ConvergenceReport> convergence;
    if (!options.referencePath.empty()) {
        convergence.emplace(referenceFromFile(options, settings));
    } else if (!options.reportPath.empty()) {
        RenderSettings referenceSettings = settings;
        referenceSettings.samplesPerPixel = settings.samplesPerPixel * kReferenceSampleFactor;
        referenceSettings.seed = settings.seed + 1;
        const std::string source = std::string(context ? "gpu" : "cpu") + " render made by this run, " +
                                   std::to_string(referenceSettings.samplesPerPixel) + " spp, seed " +
                                   std::to_string(referenceSettings.seed);
        if (!options.quiet) std::fprintf(stderr, "vkrt: reference: %s\n", source.c_str());
        convergence.emplace(render(referenceSettings, "reference", {}, nullptr).image, source);
    }
    CheckpointCallback checkpoint;
    if (convergence) {
        checkpoint = [&](uint32_t samples, double renderMs, double gpuMs, const Image& image) {
            convergence->add(samples, renderMs, gpuMs, image);
        };
    }
    const RenderResult result = render(settings, context ? "gpu" : "cpu", checkpoint, &report);

    // A lost device keeps the samples the host had copied, if any.
    const bool deviceLost = result.stopped == StopReason::DeviceLost;
    const bool anySamples = result.mostSamples > 0;
    if (!deviceLost || anySamples)
        writeImage(result.image, options.outputPath, options.exposure, options.toneMap);
    report.memory.hostPeakBytes = peakResidentBytes();

    describeRun(options, scene, settings, camera, report);
    report.rays = result.rays;
    if (!options.statsPath.empty()) writeJson(toJson(report), options.statsPath);
    if (deviceLost) {
        const std::string kept =
            anySamples ? "wrote the samples done (" + std::to_string(result.fewestSamples) + " to " +
                             std::to_string(result.mostSamples) + " per pixel) to " + options.outputPath
                       : std::string("no samples were kept, nothing written");
        std::fprintf(stderr, "vkrt: error: %s; %s\n", report.deviceLost.c_str(), kept.c_str());
        return kExitRuntimeFailure;
    }
    if (convergence) writeConvergence(options, *convergence, report, settings, 1);
    if (!options.quiet) {
        const double mrays = static_cast<double>(result.rays.total()) / (report.renderMs / 1000.0) / 1e6;
        const std::string spp = report.mostSamplesRendered > report.samplesRendered
                                    ? std::to_string(report.samplesRendered) + " to " +
                                          std::to_string(report.mostSamplesRendered)
                                    : std::to_string(report.samplesRendered);
        std::fprintf(stderr, "vkrt: %swrote %s (%dx%d, %s spp) in %.0f ms, %.2f Mrays/s%s%s\n",
                     result.stopped == StopReason::Requested ? "interrupted: " : "", options.outputPath.c_str(),
                     settings.width, settings.height, spp.c_str(), report.renderMs, mrays,
                     report.gpu ? " on " : "", report.gpu ? report.gpu->deviceName.c_str() : "");
        if (result.fewestSamples == 0) {
            std::fprintf(stderr, "vkrt: warning: the render stopped before every pixel had a sample; those "
                                 "are black\n");
        }
    }
    return result.stopped == StopReason::Requested ? kExitSignalBase + gSignal : 0;
}

}  // namespace
}  // namespace vkrt

namespace {

// A failure: one line on stderr and the exit code. Under mpirun the line names the rank, and the whole job
// ends at once with that code (MPI_Abort): rank 0 never writes a partial result.
int fail(const vkrt::MpiJob& job, int exitCode, const char* message) {
    if (job.shared()) {
        std::fprintf(stderr, "vkrt: rank %d: %s\n", job.rank(), message);
        job.abort(exitCode);
    }
    std::fprintf(stderr, "vkrt: %s\n", message);
    return exitCode;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vkrt;
    // Under an MPI launcher the ranks share the render (shared_render.h); otherwise this is a job of one.
    const MpiJob job(argc, argv);
    try {
        Options options = parseOptions(argc, argv);
        if (options.help) {
            std::fputs(helpText().c_str(), stdout);
            return 0;
        }
        if (options.listDevices) {
            for (const DeviceDescription& d : listDevices()) {
                std::printf("%d: %s (%s, Vulkan %s%s%s)%s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                            d.apiVersion.c_str(), d.driver.empty() ? "" : ", ", d.driver.c_str(),
                            d.usable ? "" : " unusable: ", d.unusableBecause.c_str());
            }
            return 0;
        }
        std::signal(SIGINT, onStopSignal);
        std::signal(SIGTERM, onStopSignal);
        return run(std::move(options), job);
    } catch (const InterruptedBeforeRender&) {
        return fail(job, kExitSignalBase + (gSignal != 0 ? gSignal : SIGTERM),
                    "interrupted while rendering the reference for --report; nothing written");
    } catch (const UsageError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const SceneError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const MemoryError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const std::bad_alloc&) {
        return fail(job, kExitRuntimeFailure, "error: out of memory");
    } catch (const std::exception& e) {
        return fail(job, kExitRuntimeFailure, (std::string("error: ") + e.what()).c_str());
    }
}
