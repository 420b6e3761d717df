// Runs the numerical-stability suite (tools/stability/) and prints its table as Markdown, or as JSON with
// --json. Cases are generated on the fly; --size and --spp vary the renders.
//
//   stability_report [--size N] [--spp N] [--long-samples N] [--json] [--dump DIR]
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "gpu/shader_compiler.h"
#include "stability/stability_suite.h"

int main(int argc, char** argv) {
    using namespace vkrt;
    StabilityOptions options;
    options.sourceDir = VKRT_SOURCE_DIR;
    options.workDir = std::filesystem::temp_directory_path() / "vkrt-stability";
    options.shaderCacheDir = defaultShaderCacheDir();
    bool json = false;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&] { return i + 1 < argc ? std::stoi(argv[++i]) : 0; };
        if (flag == "--size")
            options.width = options.height = value();
        else if (flag == "--spp")
            options.samplesPerPixel = value();
        else if (flag == "--long-samples")
            options.longAccumulationSamples = value();
        else if (flag == "--json")
            json = true;
        else if (flag == "--dump" && i + 1 < argc)
            options.dumpDir = argv[++i];
        else {
            std::fprintf(
                stderr,
                "usage: stability_report [--size N] [--spp N] [--long-samples N] [--json] [--dump DIR]\n");
            return 2;
        }
    }
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
