#include "app/one_process_render.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include "app/convergence_run.h"
#include "app/exit_codes.h"
#include "app/gpu_run.h"
#include "app/progress_bar.h"
#include "app/render_summary.h"
#include "app/stop_signal.h"
#include "common/atomic_file.h"
#include "common/elapsed_time.h"
#include "cpu/reference_renderer.h"
#include "gpu/vulkan_check.h"
#include "image/image_io.h"

namespace vkrt {

int renderOneProcess(const Options& options, const PreparedRender& prepared, RunReport& report) {
    const Scene& scene = prepared.scene;
    const RenderSettings& settings = prepared.setup.settings;
    const Camera& camera = prepared.setup.camera;
    const FlatBvh& flatBvh = prepared.bvh.flat;
    const VulkanContext* context = prepared.context.get();

    // One render on the chosen device; fills `runReport` when given.
    auto render = [&](const RenderSettings& renderSettings, const char* label,
                      const CheckpointCallback& checkpoint, RunReport* runReport) {
        ProgressBar progress(label, !options.quiet);
        const auto onProgress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
        const auto renderStart = std::chrono::steady_clock::now();
        // The time limit is the render's own; the reference of --report renders all its samples.
        const StopCondition stop(&stopRequested(), runReport ? options.timeLimitSeconds : 0.0);
        // A stop asked for while the scene loaded ends here: the render's first pass would not reach every
        // pixel (and a lavapipe pipeline's compilation would be waited for in vain).
        if (stopRequested().load()) throw InterruptedBeforeRender{"before every pixel had a sample"};
        renderBegins();
        RenderResult rendered;
        // Checkpoints count their render time from here, as the stats' render_ms does: the renderer's set-up
        // (a GPU's pipeline creation) is waited for as much as its samples are.
        const auto fromRenderStart = [&](double setupMs) {
            if (!checkpoint) return CheckpointCallback{};
            return CheckpointCallback(
                [&checkpoint, setupMs](uint32_t samples, double renderMs, double gpuMs, const Image& image) {
                    checkpoint(samples, setupMs + renderMs, gpuMs, image);
                });
        };
        if (context) {
            GpuRenderer renderer(*context, scene, flatBvh, camera, renderSettings, gpuRenderOptions(options));
            rendered = renderer.render(onProgress, fromRenderStart(millisecondsSince(renderStart)),
                                       options.reportEveryMs, stop);
            // The reference of --report is all or nothing.
            if (!runReport && rendered.stopped == StopReason::DeviceLost)
                throw GpuError(renderer.report().deviceLost + " while rendering the reference for --report");
            if (runReport) {
                recordDeviceMemory(renderer, *runReport);
                runReport->gpu = gpuReportOf(options, *context, renderer);
            }
            throwOnValidationMessages(*context);
        } else {
            const ReferenceRenderer renderer(scene, flatBvh, camera, renderSettings);
            rendered = renderer.render(onProgress, fromRenderStart(millisecondsSince(renderStart)),
                                       options.reportEveryMs, stop);
        }
        if (runReport) {
            runReport->renderMs = millisecondsSince(renderStart);
            recordResult(rendered, *runReport);
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
        const RenderSettings referenceSettings = referenceRenderSettings(settings);
        const std::string source =
            announceRenderedReference(options, referenceSettings, context ? "gpu" : "cpu", 1);
        convergence.emplace(render(referenceSettings, "reference", {}, nullptr).image, source);
    }
    CheckpointCallback checkpoint;
    if (convergence) {
        checkpoint = [&](uint32_t samples, double renderMs, double gpuMs, const Image& image) {
            convergence->add(samples, renderMs, gpuMs, image);
        };
    }
    const RenderResult result = render(settings, context ? "gpu" : "cpu", checkpoint, &report);

    // The image and the stats; a lost device keeps the samples the host had copied, if any.
    const bool deviceLost = result.stopped == StopReason::DeviceLost;
    const bool anySamples = result.mostSamples > 0;
    // A device lost before any sample was kept writes nothing at all: the image and the stats of an earlier
    // run at those paths stay as they were.
    if (deviceLost && !anySamples) {
        std::fprintf(stderr, "vkrt: error: %s; no samples were kept, nothing written\n",
                     report.deviceLost.c_str());
        return kExitRuntimeFailure;
    }
    if (samplesLeftOutOfWholePixels(result, options.scenePath) || interruptedBeforeEveryPixel(result)) {
        return result.stopped == StopReason::Requested ? stoppedExitCode() : kExitRuntimeFailure;
    }
    // All of them or none: each is written under a temporary name, and they are renamed into place together
    // (a stats file that could not be written left a new image beside an earlier run's stats).
    FileBatch outputs;
    stageImage(outputs, result.image, options.outputPath, options.exposure, options.toneMap);
    describeRun(options, scene, settings, camera, report);
    writeStats(outputs, options, report);
    if (deviceLost) {
        // The report too, with the checkpoints taken before the loss (it was dropped, and an earlier run's
        // stayed beside the new image).
        if (convergence) writeConvergence(outputs, options, *convergence, report, settings, 1, false);
        outputs.commit();
        std::fprintf(
            stderr, "vkrt: error: %s; wrote the samples done (%u to %u per pixel) to %s%s\n",
            report.deviceLost.c_str(), result.fewestSamples, result.mostSamples, options.outputPath.c_str(),
            options.reportPath.empty() ? ""
                                       : (" and the checkpoints before it to " + options.reportPath).c_str());
        return kExitRuntimeFailure;
    }

    // The report and the summary.
    if (convergence) writeConvergence(outputs, options, *convergence, report, settings, 1);
    outputs.commit();
    printRenderSummary(options, report, 1);
    if (!options.quiet && result.fewestSamples == 0) {
        std::fprintf(stderr,
                     "vkrt: warning: the render stopped before every pixel had a sample; those "
                     "are black\n");
    }
    return result.stopped == StopReason::Requested ? stoppedExitCode() : 0;
}

}  // namespace vkrt
