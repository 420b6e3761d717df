// What a render returns, an image and the rays traced, and the callbacks that follow it as it forms; shared
// by the CPU reference and the GPU tracer.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "common/render_settings.h"
#include "common/stop_condition.h"
#include "image/image.h"

namespace vkrt {

struct RenderResult {
    Image image;
    RayCounters rays;
    // Samples per pixel rendered: all pixels have at least the fewest, some up to the most when the render
    // stopped part way through a pass.
    uint32_t fewestSamples = 0;
    uint32_t mostSamples = 0;
    // Samples the pixels' averages hold: those traced less the ones left out (rays.nonFiniteSamples).
    uint64_t samplesKept = 0;
    // Pixels whose averages hold no sample: not rendered yet, or every sample left out.
    uint64_t pixelsWithoutSamples = 0;
    StopReason stopped = StopReason::None;
};

// The result's image from per-pixel (rgb sum, sample count) sums, and the samples they hold.
inline void resolveSums(RenderResult& result, const std::vector<glm::dvec4>& sums, int width, int height) {
    result.image = averageOf(sums, width, height);
    result.samplesKept = 0;
    result.pixelsWithoutSamples = 0;
    for (const glm::dvec4& sum : sums) {
        result.samplesKept += static_cast<uint64_t>(sum.w);
        result.pixelsWithoutSamples += sum.w == 0.0;
    }
}

// Called as rows (CPU) or passes (GPU) finish: done out of total.
using ProgressCallback = std::function<void(uint64_t done, uint64_t total)>;

// Called with the image so far at checkpoints of a progressive render: samples per pixel done, render time
// so far (checkpoints excluded) and GPU time (kNoGpuTime on the CPU, and for a job of several ranks).
using CheckpointCallback =
    std::function<void(uint32_t samples, double renderMs, double gpuMs, const Image& image)>;

// The GPU time of a checkpoint that has none of its own (reports leave it empty, null in JSON).
inline constexpr double kNoGpuTime = std::numeric_limits<double>::quiet_NaN();

}  // namespace vkrt
