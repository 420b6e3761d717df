// What a render returns, an image and the rays traced, and the callbacks that follow it as it forms; shared
// by the CPU reference and the GPU tracer.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>

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
    StopReason stopped = StopReason::None;
};

// Called as rows (CPU) or passes (GPU) finish: done out of total.
using ProgressCallback = std::function<void(uint64_t done, uint64_t total)>;

// Called with the image so far at checkpoints of a progressive render: samples per pixel done, render time
// so far (checkpoints excluded) and GPU time (kNoGpuTime on the CPU, and for a job of several ranks).
using CheckpointCallback =
    std::function<void(uint32_t samples, double renderMs, double gpuMs, const Image& image)>;

// The GPU time of a checkpoint that has none of its own (reports leave it empty, null in JSON).
inline constexpr double kNoGpuTime = std::numeric_limits<double>::quiet_NaN();

}  // namespace vkrt
