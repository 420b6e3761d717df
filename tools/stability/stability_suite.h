// The numerical-stability suite: stiff and extreme cases (scale, distance from the origin, grazing
// angles, thin media, total internal reflection, degenerate geometry, watertightness, extreme values),
// each rendered on the GPU and by the double-precision CPU reference and measured. Shared by
// tools/stability_report.cpp (which prints the table) and tests/stability_test.cpp (which asserts it).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gpu/vulkan_context.h"

namespace vkrt {

// Which cases run: all of them, all but the analytic shapes' (VKRT_shape, VKRT_csg), or only those.
enum class StabilityCases { All, WithoutShapes, ShapesOnly };

struct StabilityOptions {
    std::filesystem::path sourceDir;  // for scenes/cornell.gltf, scenes/whitted.gltf and scenes/csg.gltf
    std::filesystem::path workDir;    // generated variants go here
    std::string shaderCacheDir;
    int width = 48;
    int height = 48;
    int samplesPerPixel = 4;
    int longAccumulationSamples = 100000;
    std::filesystem::path dumpDir;  // when set, every case's images go here: NAME-image.pfm (GPU),
                                    // NAME-reference.pfm (CPU) and NAME-difference.pfm
    StabilityCases cases = StabilityCases::All;
};

struct StabilityResult {
    std::string group;
    std::string name;
    uint64_t nonFiniteSamples = 0;  // GPU and CPU together
    double gpuVsCpuOff = 0.0;       // fraction of pixels off by more than 1% (+ 2e-3 absolute)
    double gpuVsCpuMeanRelative = 0.0;
    std::optional<double> invarianceOff;  // against the unit-scale / untranslated / unchanged image
    std::optional<double> invarianceMeanRelative;
    std::optional<uint64_t> leaks;      // rays aimed at shared edges and vertices (or into a solid) that
                                        // got through, GPU and CPU together
    std::optional<uint64_t> wrongHits;  // rays that hit where nothing is, at another distance, or on another
                                        // face than the expected one or a face inside a solid (ray cases)
    std::optional<double> acne;         // fraction of lit pixels darker than the closed form by > 1%
    std::optional<double> accumulationError;  // relative error of a long accumulation of a constant
    std::string note;  // ray cases: what went wrong, counted by kind, and the first such ray described
};

std::vector<StabilityResult> runStabilitySuite(const VulkanContext& context, const StabilityOptions& options);

// The analytic shapes' cases alone (runStabilitySuite includes them unless told not to): grazing rays on a
// box's faces, a cylinder's side and a cone's rulings; rays through edges, corners, the apex and CSG rims,
// +-1 ulp; operands with coincident faces against the same solids without them; scales 1e-4 and 1e4.
std::vector<StabilityResult> runShapeStabilityCases(const VulkanContext& context,
                                                    const StabilityOptions& options);

// The results as a Markdown table.
std::string stabilityTable(const std::vector<StabilityResult>& results);

}  // namespace vkrt
