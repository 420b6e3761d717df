// One render shared by the ranks of an MPI job. A render is a set of (pixel, sample index) pairs, and a
// sample's value depends on its pixel and index alone (counter-based random numbers), so the ranks split the
// sample indices: each takes whole-image batches [first, end) from a counter on rank 0 until none are left,
// sizing its batches by its own speed, so that a GPU beside a CPU takes more of them and both finish
// together. Rank 0 then sums every rank's per-pixel sums and counts: the image equals one process's with the
// same seed, to rounding.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "app/mpi_job.h"
#include "app/render_stats.h"
#include "image/render_result.h"

namespace vkrt {

// Adds samples [first, end) of every pixel into `sums`, stopping part way when `stop` says so.
using BatchRenderer = std::function<RenderResult(uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums,
                                                 const StopCondition& stop)>;

// What one rank rendered.
struct RankShare {
    std::vector<glm::dvec4> sums;  // per pixel: rgb sums and finite-sample counts
    RayCounters rays;
    // Samples per pixel, summed over the rank's batches: every pixel has at least `fewest` of this rank's, at
    // most `most` (they differ only when a batch was cut short, and only the last one can be). Summed over
    // the ranks they only bound the job's, whose short pixels differ by rank: combineShares counts the summed
    // sums.
    uint64_t fewest = 0;
    uint64_t most = 0;
    uint32_t batches = 0;
    std::chrono::steady_clock::time_point started;  // when the ranks started together
    double renderMs = 0.0;  // from then to the end of this rank's last batch
    StopReason stopped = StopReason::None;
    bool abandoned = false;  // the other ranks never came to the end: the job is lost, nothing may be written
};

struct ShareOptions {
    // A batch is sized, from the rank's speed so far, to take about this long; and to at most half of what
    // is left divided by the ranks, so that the last batches are small and the ranks end together.
    double batchTargetMs = 250.0;
    // Set by SIGINT, SIGTERM and SIGHUP. Once it is, a rank waits at most abandonAfterSeconds for the others
    // at the end (when a rank fails, Open MPI ends the others by SIGTERM, and they must not wait for it
    // forever).
    const std::atomic<bool>* stopRequested = nullptr;
    double abandonAfterSeconds = 5.0;
    // Error against run time (--report): called on rank 0 with the sums of samples [0, samples) of every
    // pixel at every power of two of samples and at the end (and, with checkpointEveryMs > 0, after any phase
    // that crosses that much render time), the checkpoint schedule one process follows. The ranks then render
    // in phases that end at those sample counts, every rank together, and wait for each other at each.
    std::function<void(uint32_t samples, double renderMs, const std::vector<glm::dvec4>& sums)> checkpoint;
    double checkpointEveryMs = 0.0;  // the same on every rank
    // When rank 0's renderer began its set-up: checkpoints' render times count from there, as the stats'
    // render_ms and one process's do (the ranks' set-ups, a GPU's pipeline among them, are waited for).
    std::chrono::steady_clock::time_point setupStarted{};
    size_t pixels = 0;               // the image's, for the sums
};

// Every rank renders its share of samplesPerPixel samples of every pixel. Collective: every rank calls it,
// after its renderer is ready; the ranks start together (a barrier), and `stop`'s clock starts there. A rank
// that is asked to stop (time limit, signal) ends its batch there and tells the others to take no more.
// `progress` is called as batches are handed out (samples out of samplesPerPixel).
RankShare renderShare(const MpiJob& job, uint32_t samplesPerPixel, const BatchRenderer& renderBatch,
                      StopCondition stop, const ProgressCallback& progress = {},
                      const ShareOptions& options = {});

// The whole render on rank 0: every rank's sums added up and averaged, rays summed, the samples per pixel (at
// least and at most), why it stopped (an interrupt on any rank, else the time limit on any). `ranks` gets
// every rank's entry, in rank order (rank 0 only). Collective.
RenderResult combineShares(const MpiJob& job, RankShare& share, const RunReport::Rank& mine, int width,
                           int height, std::vector<RunReport::Rank>& ranks);

}  // namespace vkrt
