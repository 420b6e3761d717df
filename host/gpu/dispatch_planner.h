// How much each GPU dispatch traces: rows x samples sized from measured times to take about a target time
// (a real GPU's watchdog must never fire, and a stop request is honoured after the dispatch that sees it).
// Plain arithmetic, no Vulkan, so that the policy is tested on its own.
#pragma once

#include <cstdint>
#include <vector>

namespace vkrt {

class DispatchPlanner {
  public:
    // An image of `height` rows, dispatches of about `targetMs`; a batch of several samples a pixel keeps at
    // least `fewestRows` rows a dispatch (enough invocations for the device to run at once). `loopBudget`:
    // the loop passes an invocation may take in a dispatch (llvmpipe's), 0 for none.
    DispatchPlanner(uint32_t height, double targetMs, uint32_t fewestRows, uint32_t loopBudget = 0);

    // Samples a pixel for the batch that starts at sample `sample` over rows [tile, tileEnd): at most
    // `most`. The render's first sample sweeps every row before any row gets a second, so that a render
    // stopped early has them all; later batches take as many samples as the target time allows over
    // `fewestRows` rows. (Whitted's kernel walks all of an invocation's samples in one loop, so its SIMD
    // lanes wait for the largest sum of their ray trees, not for the largest tree of each sample.)
    uint32_t batchSamples(uint32_t sample, uint32_t most, uint32_t tile, uint32_t tileEnd) const;

    // Rows from `row` (at least one, at most to tileEnd) for a dispatch of `samples` a pixel: as many as the
    // target time holds, each at the cost measured when it was last traced (rows not traced yet at the
    // recent speed), and at most twice the largest dispatch so far in rows x samples.
    uint32_t rows(uint32_t row, uint32_t tileEnd, uint32_t samples) const;

    // A dispatch of rows [row, row + rows) at `samples` a pixel took `ms`.
    void record(uint32_t row, uint32_t rows, uint32_t samples, double ms);

    // A dispatch lost samples (not finite, or walks that llvmpipe's loop budget cut short: it counts the
    // iterations of all of an invocation's samples together). Batches take one sample from then on.
    void samplesLost() { oneSampleAtATime_ = true; }

    // With a loop budget, the most loop passes a sample has taken so far (the kernel's count). Until one is
    // known, batches take one sample; then as many as fit a quarter of the budget.
    void loopPassesPerSample(uint32_t passes);

    double targetMs() const { return targetMs_; }
    uint32_t loopBudget() const { return loopBudget_; }

  private:
    // Rows x samples the target time holds at the recent speed, within the growth cap.
    double units() const;

    double targetMs_;
    uint32_t fewestRows_;
    std::vector<double> rowMs_;  // ms a sample of each row took when last traced; 0: not traced yet
    double recentUnits_ = 0.0, recentMs_ = 0.0;  // decaying sums of recent dispatches' sizes and times
    double largestUnits_ = 1.0;                  // rows x samples of the largest dispatch so far
    bool oneSampleAtATime_ = false;
    uint32_t loopBudget_ = 0;
    uint32_t budgetSamples_ = 1;  // samples a batch within the loop budget
};

}  // namespace vkrt
