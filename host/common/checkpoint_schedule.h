// When the passes of a progressive render end and which of them end with a checkpoint, shared by the CPU
// reference and the GPU tracer so that both report at the same sample counts.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "common/elapsed_time.h"

namespace vkrt {

// Without checkpoints a render may run all its samples in one pass. With them, passes end at every power
// of two of samples (and at the last sample), where a checkpoint is taken; with checkpointEveryMs > 0, any
// pass that crosses that much render time since the last checkpoint ends with one too. Render time starts
// when the schedule is made and excludes the time spent in checkpoint callbacks.
class CheckpointSchedule {
  public:
    CheckpointSchedule(uint32_t samplesPerPixel, bool checkpoints, double checkpointEveryMs)
        : samplesPerPixel_(samplesPerPixel), checkpoints_(checkpoints), everyMs_(checkpointEveryMs) {}

    // The sample count that the pass starting after `done` samples must not go past.
    uint32_t boundary(uint32_t done) const {
        if (!checkpoints_) return samplesPerPixel_;
        uint32_t next = 1;
        while (next <= done) next *= 2;
        return std::min(next, samplesPerPixel_);
    }

    // The end of the next pass for a renderer whose pass covers the whole image: the boundary, or, with
    // checkpoints by time, a quarter of the way there (at least one sample), so that passes are short
    // enough to notice the time.
    uint32_t passEnd(uint32_t done) const {
        const uint32_t end = boundary(done);
        if (!checkpoints_ || everyMs_ <= 0.0) return end;
        return std::min(end, done + std::max(1u, (end - done) / 4));
    }

    // Milliseconds since the schedule was made, less those spent in checkpoints.
    double renderMs() const { return millisecondsSince(start_) - pausedMs_; }

    // Whether the pass that brought the render to `done` samples, `renderMs` into it, ends with a
    // checkpoint.
    bool due(uint32_t done, double renderMs) const {
        if (!checkpoints_) return false;
        const bool powerOfTwo = (done & (done - 1)) == 0;
        return powerOfTwo || done == samplesPerPixel_ ||
               (everyMs_ > 0.0 && renderMs - lastCheckpointMs_ >= everyMs_);
    }

    // Runs the checkpoint callback, keeping its time out of renderMs().
    template <typename Callback>
    void take(double renderMs, Callback&& takeCheckpoint) {
        const auto pause = std::chrono::steady_clock::now();
        takeCheckpoint();
        lastCheckpointMs_ = renderMs;
        pausedMs_ += millisecondsSince(pause);
    }

  private:
    uint32_t samplesPerPixel_;
    bool checkpoints_;
    double everyMs_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    double pausedMs_ = 0.0;
    double lastCheckpointMs_ = 0.0;
};

}  // namespace vkrt
