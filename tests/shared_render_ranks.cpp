// A shared render of two pixels whose ranks' batches are cut short at different pixels, for mpi_test to run
// under mpirun: rank r's one batch leaves pixel r without its sample and says it was interrupted. Each rank's
// fewest is then 0, yet every pixel has one sample (the other rank's). Rank 0 prints the job's samples per
// pixel, "fewest most".
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "app/mpi_job.h"
#include "app/shared_render.h"

int main(int argc, char** argv) {
    const vkrt::MpiJob job(argc, argv);
    vkrt::ShareOptions options;
    options.pixels = 2;
    const auto cutShort = [&](uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums,
                              const vkrt::StopCondition&) {
        // Long enough that the other rank takes its batch before this one's stop closes the counter.
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        for (size_t pixel = 0; pixel < sums.size(); ++pixel) {
            if (pixel != static_cast<size_t>(job.rank()))
                sums[pixel] += glm::dvec4(1.0, 1.0, 1.0, end - first);
        }
        vkrt::RenderResult batch;
        batch.fewestSamples = 0;
        batch.mostSamples = end - first;
        batch.stopped = vkrt::StopReason::Requested;
        return batch;
    };
    // Two samples a pixel: one batch of one sample each.
    vkrt::RankShare share = vkrt::renderShare(job, 2, cutShort, vkrt::StopCondition(), {}, options);
    vkrt::RunReport::Rank mine;
    mine.samples = share.fewest;
    mine.samplesMax = share.most;
    mine.batches = share.batches;
    std::vector<vkrt::RunReport::Rank> ranks;
    const vkrt::RenderResult result = vkrt::combineShares(job, share, mine, 2, 1, ranks);
    if (job.rank() == 0) std::printf("%u %u\n", result.fewestSamples, result.mostSamples);
    return 0;
}
