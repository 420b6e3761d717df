#include "app/shared_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/checkpoint_schedule.h"
#include "common/elapsed_time.h"

#include <nlohmann/json.hpp>

namespace vkrt {
namespace {

// Added to the counter by a rank that stops: no batch is handed out after it.
constexpr uint64_t kClosed = uint64_t{1} << 40;

nlohmann::json toJson(const RunReport::Rank& r) {
    return {{"device", r.device},
            {"device_name", r.deviceName},
            {"spp", r.samples},
            {"spp_max", r.samplesMax},
            {"batches", r.batches},
            {"render_ms", r.renderMs},
            {"rays", {r.rays.primary, r.rays.shadow, r.rays.secondary, r.rays.nonFiniteSamples}}};
}

RunReport::Rank rankFromJson(const nlohmann::json& j) {
    RunReport::Rank r;
    r.device = j.at("device");
    r.deviceName = j.at("device_name");
    r.samples = j.at("spp");
    r.samplesMax = j.at("spp_max");
    r.batches = j.at("batches");
    r.renderMs = j.at("render_ms");
    r.rays.primary = j.at("rays")[0];
    r.rays.shadow = j.at("rays")[1];
    r.rays.secondary = j.at("rays")[2];
    r.rays.nonFiniteSamples = j.at("rays")[3];
    return r;
}

// The samples per pixel of the whole job, at least and at most, on rank 0: from the summed sums' counts, and
// from the ranks' RankShare::fewest and ::most summed, which only bound them (the pixels one rank's last
// batch left short are not those another's did: the fewest summed read 166 where every pixel had 170). A
// count holds a pixel's finite samples alone: with none left out it is the samples traced; with some, the
// pixel traced its count and up to all `leftOut` more, and each end is the tighter of the two bounds.
struct PixelSampleRange {
    uint64_t fewest = 0;
    uint64_t most = 0;
};

PixelSampleRange samplesEveryPixelHas(const std::vector<glm::dvec4>& sums, uint64_t summedFewest,
                                      uint64_t summedMost, uint64_t leftOut) {
    double fewestCount = std::numeric_limits<double>::infinity(), mostCount = 0.0;
    for (const glm::dvec4& s : sums) {
        fewestCount = std::min(fewestCount, s.w);
        mostCount = std::max(mostCount, s.w);
    }
    return {std::max(summedFewest, static_cast<uint64_t>(fewestCount)),
            std::min(summedMost, static_cast<uint64_t>(mostCount) + leftOut)};
}

}  // namespace

RankShare renderShare(const MpiJob& job, uint32_t samplesPerPixel, const BatchRenderer& renderBatch,
                      StopCondition stop, const ProgressCallback& progress, const ShareOptions& options) {
    RankShare share;
    SharedCounter counter(job);
    // The sums before the clock starts (ReferenceRenderer::render says why).
    share.sums.resize(options.pixels, glm::dvec4(0.0));
    job.barrier();
    stop.start();
    share.started = std::chrono::steady_clock::now();
    const double setupMs =
        options.setupStarted == std::chrono::steady_clock::time_point{}
            ? 0.0
            : std::chrono::duration<double, std::milli>(share.started - options.setupStarted).count();
    const uint64_t spp = samplesPerPixel;
    // With checkpoints, phases: the samples of each phase [done, phaseEnd) are handed out, every rank renders
    // its batches of them, and the ranks meet at its end for the checkpoint. Rank 0's schedule decides by time.
    const bool phased = job.fromRoot(static_cast<bool>(options.checkpoint));
    CheckpointSchedule schedule(samplesPerPixel, phased, options.checkpointEveryMs);
    uint64_t done = 0;
    uint64_t checkpointed = 0;  // the samples of the last checkpoint's image
    uint64_t phaseEnd = phased ? schedule.passEnd(0) : spp;
    // The first batch is one sample: it measures the rank's speed.
    uint64_t count = 1;
    double samplesPerMs = 0.0;
    for (;;) {
        uint64_t first = share.stopped != StopReason::None ? phaseEnd : counter.fetchAdd(count);
        // Asked to stop between batches (every rank takes at least one): the samples just taken are left, and
        // the others take no more either. Only while samples were left to take: a time limit or a signal
        // after the last one stops nothing, as in one process.
        if (first < phaseEnd && share.stopped == StopReason::None && share.batches > 0 && stop.stop()) {
            share.stopped = stop.reason();
            counter.fetchAdd(kClosed);
            first = phaseEnd;
        }
        if (first >= phaseEnd) {
            if (!phased) break;
            // The phase's end, every rank together: stop if any rank stopped, else a checkpoint when due.
            if (options.stopRequested &&
                !job.barrierUnlessAbandoned(*options.stopRequested, options.abandonAfterSeconds)) {
                share.abandoned = true;
                return share;
            }
            if (job.anyRank(share.stopped != StopReason::None)) {
                // Stopped between checkpoints: the report ends with the image the ranks write, counted by the
                // samples every pixel has, as one process's does and as combineShares counts them.
                std::vector<glm::dvec4> sums = share.sums;
                job.sumToRoot(&sums[0].x, sums.size() * 4);
                uint64_t bounds[] = {share.fewest, share.most, share.rays.nonFiniteSamples};
                job.sumToRoot(bounds, std::size(bounds));
                if (job.rank() == 0) {
                    const PixelSampleRange samples =
                        samplesEveryPixelHas(sums, bounds[0], bounds[1], bounds[2]);
                    if (samples.fewest != checkpointed || samples.most > samples.fewest) {
                        const double renderMs = schedule.renderMs();
                        schedule.take(renderMs, [&] {
                            options.checkpoint(static_cast<uint32_t>(samples.fewest), setupMs + renderMs,
                                               sums);
                        });
                    }
                }
                break;
            }
            done = phaseEnd;
            if (job.rank() == 0) counter.set(done);
            const double renderMs = schedule.renderMs();
            if (job.fromRoot(job.rank() == 0 && schedule.due(static_cast<uint32_t>(done), renderMs))) {
                std::vector<glm::dvec4> sums = share.sums;
                job.sumToRoot(&sums[0].x, sums.size() * 4);
                if (job.rank() == 0) {
                    schedule.take(renderMs, [&] {
                        options.checkpoint(static_cast<uint32_t>(done), setupMs + renderMs, sums);
                    });
                }
                checkpointed = done;
            }
            job.barrier();  // the counter restarts at `done` before anyone adds to it
            if (done >= spp) break;
            phaseEnd = schedule.passEnd(static_cast<uint32_t>(done));
            continue;
        }
        const uint64_t end = std::min(first + count, phaseEnd);
        if (progress) progress(end, spp);
        const auto batchStart = std::chrono::steady_clock::now();
        const RenderResult batch =
            renderBatch(static_cast<uint32_t>(first), static_cast<uint32_t>(end), share.sums, stop);
        const double batchMs = millisecondsSince(batchStart);
        ++share.batches;
        share.rays += batch.rays;
        share.fewest += batch.fewestSamples;
        share.most += batch.mostSamples;
        if (batch.stopped != StopReason::None) {
            share.stopped = batch.stopped;
            counter.fetchAdd(kClosed);
            continue;  // to the phase's end, where the ranks learn that one stopped
        }
        // The next batch: about batchTargetMs at this rank's speed, at most half of what is left per rank.
        samplesPerMs = static_cast<double>(end - first) / std::max(batchMs, 0.01);
        const uint64_t left = phaseEnd - std::min(phaseEnd, end);
        const double byTime = std::floor(samplesPerMs * options.batchTargetMs);
        const double byShare = std::floor(static_cast<double>(left) / (2.0 * job.size()));
        count = static_cast<uint64_t>(std::max(1.0, std::min(byTime, byShare)));
    }
    share.renderMs = millisecondsSince(share.started);
    // Every rank must be there before the window is freed and the sums reduced.
    if (options.stopRequested && !job.barrierUnlessAbandoned(*options.stopRequested, options.abandonAfterSeconds)) {
        share.abandoned = true;
        return share;
    }
    counter.free();
    return share;
}

RenderResult combineShares(const MpiJob& job, RankShare& share, const RunReport::Rank& mine, int width,
                           int height, std::vector<RunReport::Rank>& ranks) {
    // renderShare sized the sums before its first batch; this only keeps the reduction safe if it did not.
    share.sums.resize(static_cast<size_t>(width) * height, glm::dvec4(0.0));
    static_assert(sizeof(glm::dvec4) == 4 * sizeof(double), "sums are reduced as doubles");
    job.sumToRoot(&share.sums[0].x, share.sums.size() * 4);
    uint64_t totals[] = {share.rays.primary,
                         share.rays.shadow,
                         share.rays.secondary,
                         share.rays.nonFiniteSamples,
                         share.fewest,
                         share.most,
                         share.stopped == StopReason::Requested ? 1u : 0u,
                         share.stopped == StopReason::TimeLimit ? 1u : 0u};
    job.sumToRoot(totals, std::size(totals));
    const std::vector<std::string> entries = job.gatherToRoot(toJson(mine).dump());

    RenderResult result;
    if (job.rank() != 0) return result;
    for (const std::string& entry : entries) ranks.push_back(rankFromJson(nlohmann::json::parse(entry)));
    result.rays = {totals[0], totals[1], totals[2], totals[3]};
    const PixelSampleRange samples = samplesEveryPixelHas(share.sums, totals[4], totals[5], totals[3]);
    result.fewestSamples = static_cast<uint32_t>(samples.fewest);
    result.mostSamples = static_cast<uint32_t>(samples.most);
    result.stopped = totals[6] > 0   ? StopReason::Requested
                     : totals[7] > 0 ? StopReason::TimeLimit
                                     : StopReason::None;
    resolveSums(result, share.sums, width, height);
    return result;
}

}  // namespace vkrt
