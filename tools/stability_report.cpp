// Runs the numerical-stability suite (tools/stability/) and prints its table as Markdown, or as JSON with
// --json. Cases are generated on the fly; --size and --spp vary the renders.
//
//   stability_report [--size N] [--spp N] [--long-samples N] [--json] [--dump DIR]
//   (--help lists every option with its range; a bad argument prints one line and exits 2)
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "command_line.h"
#include "gpu/shader_compiler.h"
#include "stability/stability_suite.h"

int main(int argc, char** argv) {
    using namespace vkrt;
    StabilityOptions options;
    options.sourceDir = VKRT_SOURCE_DIR;
    options.workDir = std::filesystem::temp_directory_path() / "vkrt-stability";
    options.shaderCacheDir = defaultShaderCacheDir();
    bool json = false;
    int size = options.width;
    CLI::App app{"Runs the numerical-stability suite and prints its table.", "stability_report"};
    app.add_option("--size", size, "image width and height")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_option("--spp", options.samplesPerPixel, "samples per pixel")
        ->check(CLI::Range(1, 1'000'000))
        ->capture_default_str();
    app.add_option("--long-samples", options.longAccumulationSamples, "samples of the long accumulation")
        ->check(CLI::Range(1, 100'000'000))
        ->capture_default_str();
    app.add_flag("--json", json, "JSON instead of a Markdown table");
    app.add_option("--dump", options.dumpDir, "write every case's images into this folder");
    if (const std::optional<int> exitCode = parseCommandLine(app, argc, argv)) return *exitCode;
    options.width = options.height = size;
    try {
        const VulkanContext context;
        const auto results = runStabilitySuite(context, options);
        if (!json) {
            std::printf("Device: %s\n\n%s", context.description().name.c_str(),
                        stabilityTable(results).c_str());
            return 0;
        }
        nlohmann::json out = nlohmann::json::array();
        for (const StabilityResult& r : results) {
            nlohmann::json row = {{"group", r.group},
                                  {"case", r.name},
                                  {"nonfinite_samples", r.nonFiniteSamples},
                                  {"gpu_vs_cpu_off", r.gpuVsCpuOff},
                                  {"gpu_vs_cpu_mean_relative", r.gpuVsCpuMeanRelative}};
            if (r.invarianceOff) row["invariance_off"] = *r.invarianceOff;
            if (r.invarianceMeanRelative) row["invariance_mean_relative"] = *r.invarianceMeanRelative;
            if (r.leaks) row["leaks"] = *r.leaks;
            if (r.wrongHits) row["wrong_hits"] = *r.wrongHits;
            if (!r.note.empty()) row["note"] = r.note;
            if (r.acne) row["acne"] = *r.acne;
            if (r.accumulationError) row["accumulation_error"] = *r.accumulationError;
            out.push_back(row);
        }
        std::printf("%s\n", out.dump(2).c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "stability_report: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
