#include "gpu/dispatch_planner.h"

#include <algorithm>

namespace vkrt {

DispatchPlanner::DispatchPlanner(uint32_t height, double targetMs, uint32_t fewestRows, uint32_t loopBudget)
    : targetMs_(targetMs),
      fewestRows_(std::max(fewestRows, 1u)),
      rowMs_(height, 0.0),
      loopBudget_(loopBudget) {}

void DispatchPlanner::loopPassesPerSample(uint32_t passes) {
    // A quarter of the budget. The kernel counts each lane's passes and reports the SIMD group's largest, but
    // the group runs a loop as long as any lane needs it: counted per group instead, the passes were up to
    // 1.7 times as many (the csg scene with Whitted; 1.0 to 1.5 on the engine, the helmet, the glossy and
    // Whitted scenes). The count also leaves out a few short loops (table searches, CSG intervals), and
    // samples of one pixel differ.
    if (loopBudget_ > 0 && passes > 0) budgetSamples_ = std::max(1u, loopBudget_ / 4 / passes);
}

double DispatchPlanner::units() const {
    // Before any dispatch: the smallest, one row at one sample. Growth is capped at twice the largest
    // dispatch so far, not the last: the last of a sweep holds the rows left over, often one, and capping at
    // twice that restarted the ramp from one row at every sweep (issue 13).
    if (recentMs_ <= 0.0) return largestUnits_;
    return std::clamp(recentUnits_ / recentMs_ * targetMs_, 1.0, 2.0 * largestUnits_);
}

uint32_t DispatchPlanner::batchSamples(uint32_t sample, uint32_t most, uint32_t tile,
                                       uint32_t tileEnd) const {
    if (oneSampleAtATime_) return 1;
    if (loopBudget_ > 0) most = std::min(most, budgetSamples_);
    const uint32_t tileRows = tileEnd - tile;
    const double rowsPerBatch = sample == 0 ? tileRows : std::min(fewestRows_, tileRows);
    return static_cast<uint32_t>(
        std::clamp(units() / rowsPerBatch, 1.0, static_cast<double>(std::max(most, 1u))));
}

uint32_t DispatchPlanner::rows(uint32_t row, uint32_t tileEnd, uint32_t samples) const {
    const uint32_t most =
        static_cast<uint32_t>(std::clamp(units() / samples, 1.0, static_cast<double>(tileEnd - row)));
    if (recentMs_ <= 0.0) return most;
    const double unmeasuredMs = recentMs_ / recentUnits_;  // a row-sample at the recent speed
    double ms = 0.0;
    uint32_t rows = 0;
    while (rows < most) {
        const double rowMs = rowMs_[row + rows];
        const double cost = samples * (rowMs > 0.0 ? rowMs : unmeasuredMs);
        if (rows > 0 && ms + cost > targetMs_) break;
        ms += cost;
        ++rows;
    }
    return rows;
}

void DispatchPlanner::record(uint32_t row, uint32_t rows, uint32_t samples, double ms) {
    const double units = static_cast<double>(rows) * samples;
    largestUnits_ = std::max(largestUnits_, units);
    // The speed of the recent dispatches, each weighed by its size and halved at every dispatch since: a
    // sweep's last dispatch is often a row or two, whose few milliseconds are mostly overhead.
    ms = std::max(ms, 0.01);
    const bool first = recentMs_ <= 0.0;
    recentUnits_ = 0.5 * recentUnits_ + units;
    recentMs_ = 0.5 * recentMs_ + ms;
    // Bands of an image differ in cost (sky against glass): each row remembers its band's. Not from the first
    // dispatch, which also pays the device's warm-up (lavapipe compiles the kernel then).
    if (first) return;
    for (uint32_t r = row; r < row + rows; ++r) rowMs_[r] = ms / units;
}

}  // namespace vkrt
