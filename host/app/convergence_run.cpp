#include "app/convergence_run.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "app/host_memory.h"
#include "image/image_io.h"

namespace vkrt {
namespace {

// A reference made for a report without --reference has this many times the samples of the render.
constexpr int kReferenceSampleFactor = 16;

}  // namespace

ConvergenceReport referenceFromFile(const Options& options, const RenderSettings& settings) {
    Image reference;
    try {
        reference = readImage(options.referencePath, hostMemoryFor(options).bytes);
    } catch (const ImageError& e) {
        throw UsageError(std::string("--reference: ") + e.what());
    } catch (const MemoryError& e) {
        throw MemoryError(std::string("--reference: ") + e.what());
    }
    if (reference.width != settings.width || reference.height != settings.height) {
        throw UsageError("--reference: " + options.referencePath + " is " + std::to_string(reference.width) +
                         "x" + std::to_string(reference.height) + ", the render " +
                         std::to_string(settings.width) + "x" + std::to_string(settings.height));
    }
    // Finite, or every error measured against it would not be. (Small negative values, from filters with
    // negative lobes or gamut conversions, are measured as they are.)
    for (int y = 0; y < reference.height; ++y) {
        for (int x = 0; x < reference.width; ++x) {
            const glm::vec3 texel = reference.at(x, y);
            if (!std::isfinite(texel.x) || !std::isfinite(texel.y) || !std::isfinite(texel.z)) {
                throw UsageError("--reference: " + options.referencePath + ": pixel (" + std::to_string(x) +
                                 ", " + std::to_string(y) + ") is not finite");
            }
        }
    }
    return ConvergenceReport(std::move(reference), "file " + options.referencePath);
}

RenderSettings referenceRenderSettings(const RenderSettings& settings) {
    RenderSettings referenceSettings = settings;
    referenceSettings.samplesPerPixel = settings.samplesPerPixel * kReferenceSampleFactor;
    // The next seed, within --seed's range (0 after its largest), so that the reference can be rendered
    // again.
    referenceSettings.seed = settings.seed >= kMaxSeed ? 0u : settings.seed + 1;
    return referenceSettings;
}

std::string announceRenderedReference(const Options& options, const RenderSettings& referenceSettings,
                                      const std::string& device, int ranks) {
    const std::string by = ranks > 1 ? " on " + std::to_string(ranks) + " ranks" : std::string();
    const std::string source = device + " render made by this run" + by + ", " +
                               std::to_string(referenceSettings.samplesPerPixel) + " spp, seed " +
                               std::to_string(referenceSettings.seed);
    if (!options.quiet) std::fprintf(stderr, "vkrt: reference: %s\n", source.c_str());
    // The reference is all or nothing: the time limit is the render's own, and does not shorten it.
    if (options.timeLimitSeconds > 0.0 && !options.quiet) {
        std::fprintf(
            stderr,
            "vkrt: warning: --time-limit does not bound this reference (%d spp); give --reference to "
            "measure against a file instead\n",
            referenceSettings.samplesPerPixel);
    }
    return source;
}

void writeConvergence(FileBatch& batch, const Options& options, const ConvergenceReport& convergence,
                      const RunReport& report, const RenderSettings& settings, int ranks, bool summarise) {
    // The report, with what was rendered.
    if (!options.reportPath.empty()) {
        nlohmann::json context = {
            {"scene", options.scenePath},
            {"device", report.device},
            {"device_name", report.gpu ? report.gpu->deviceName : std::string("cpu reference")},
            {"width", settings.width},
            {"height", settings.height},
            {"spp", report.samplesRendered},
            {"spp_requested", settings.samplesPerPixel},
            {"integrator", integratorName(settings.integrator)},
            {"max_depth", settings.maxDepth},
            {"light_samples", settings.lightSamples},
            {"seed", settings.seed}};
        // What else makes the image, as the stats name it.
        if (!options.environmentPath.empty()) context["environment"] = options.environmentPath;
        if (ranks > 1) context["ranks"] = ranks;
        convergence.write(batch, options.reportPath, context);
    }
    // The error at the last checkpoint.
    if (summarise && !options.quiet && !convergence.points().empty()) {
        const ConvergencePoint& last = convergence.points().back();
        std::fprintf(stderr,
                     "vkrt: against the reference: RMSE %.4g, relMSE %.4g, %.2f%% of pixels off by >1%%\n",
                     last.rmse, last.relMse, 100.0 * last.fractionOff);
    }
}

}  // namespace vkrt
