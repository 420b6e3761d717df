// When a render ends before its last sample: on a request from outside (a signal handler sets the flag) or at
// a time limit. Renderers ask between units of work (a GPU dispatch, a CPU pixel), so a render stops within
// one unit; pixels keep their own sample counts, so an image stopped part way through a pass is still the
// average of each pixel's samples.
#pragma once

#include <atomic>
#include <chrono>

namespace vkrt {

// DeviceLost is set by the GPU renderer, not by a StopCondition: the device stopped working.
enum class StopReason { None, Requested, TimeLimit, DeviceLost };

class StopCondition {
  public:
    StopCondition() = default;
    // `flag` (may be null) is read, never written; timeLimitSeconds <= 0: none.
    StopCondition(const std::atomic<bool>* flag, double timeLimitSeconds)
        : flag_(flag), limitSeconds_(timeLimitSeconds) {}

    // Starts the clock of the time limit.
    void start() { start_ = std::chrono::steady_clock::now(); }

    StopReason reason() const {
        if (flag_ && flag_->load(std::memory_order_relaxed)) return StopReason::Requested;
        if (limitSeconds_ > 0.0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >= limitSeconds_)
            return StopReason::TimeLimit;
        return StopReason::None;
    }
    bool stop() const { return reason() != StopReason::None; }

  private:
    const std::atomic<bool>* flag_ = nullptr;
    double limitSeconds_ = 0.0;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace vkrt
