// host/common: the checkpoint schedule both renderers follow, the parallel loop and fork-join.
#include <atomic>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/checkpoint_schedule.h"
#include "common/fork_join.h"
#include "common/parallel_for.h"

namespace vkrt {
namespace {

TEST(CheckpointSchedule, WithoutCheckpointsOnePassAndNoCheckpoint) {
    const CheckpointSchedule schedule(100, false, 50.0);
    EXPECT_EQ(schedule.boundary(0), 100u);
    EXPECT_EQ(schedule.passEnd(0), 100u);
    EXPECT_FALSE(schedule.due(100, 1e9));
}

TEST(CheckpointSchedule, PassesEndAtEveryPowerOfTwoAndTheLastSample) {
    const CheckpointSchedule schedule(100, true, 0.0);
    std::vector<uint32_t> ends;
    for (uint32_t done = 0; done < 100; done = schedule.passEnd(done)) ends.push_back(schedule.passEnd(done));
    EXPECT_EQ(ends, (std::vector<uint32_t>{1, 2, 4, 8, 16, 32, 64, 100}));
    for (uint32_t end : ends) EXPECT_TRUE(schedule.due(end, 0.0)) << end;
    EXPECT_FALSE(schedule.due(3, 1e9)) << "no checkpoint by time unless asked";
    EXPECT_EQ(schedule.boundary(5), 8u);
}

TEST(CheckpointSchedule, CheckpointsByTimeSplitPassesIntoQuarters) {
    CheckpointSchedule schedule(64, true, 10.0);
    EXPECT_EQ(schedule.passEnd(0), 1u);
    EXPECT_EQ(schedule.passEnd(16), 20u);  // a quarter of the way to 32
    EXPECT_EQ(schedule.passEnd(31), 32u);
    EXPECT_EQ(schedule.boundary(16), 32u);
    EXPECT_FALSE(schedule.due(20, 9.0));
    EXPECT_TRUE(schedule.due(20, 10.0));
    schedule.take(10.0, [] {});
    EXPECT_FALSE(schedule.due(24, 15.0)) << "time counts from the last checkpoint";
    EXPECT_TRUE(schedule.due(24, 20.0));
}

TEST(CheckpointSchedule, TimeInCheckpointsIsNotRenderTime) {
    CheckpointSchedule schedule(4, true, 0.0);
    schedule.take(schedule.renderMs(), [] { std::this_thread::sleep_for(std::chrono::milliseconds(50)); });
    EXPECT_LT(schedule.renderMs(), 40.0);
}

TEST(ParallelFor, VisitsEveryIndexOnceOnAnyNumberOfThreads) {
    for (unsigned threads : {1u, 2u, 3u, 16u}) {
        std::vector<std::atomic<int>> visits(1000);
        std::atomic<bool> workerInRange{true};
        parallelFor(visits.size(), threads, [&](size_t index, unsigned worker) {
            ++visits[index];
            if (worker >= threads) workerInRange = false;
        });
        for (const std::atomic<int>& v : visits) ASSERT_EQ(v.load(), 1) << threads << " threads";
        EXPECT_TRUE(workerInRange);
    }
    int calls = 0;
    parallelFor(0, 4, [&](size_t, unsigned) { ++calls; });
    EXPECT_EQ(calls, 0);
}

TEST(ForkJoin, RunsBothHalvesSplitOrNot) {
    for (bool split : {false, true}) {
        ForkJoin forkJoin(2);
        std::atomic<int> first{0}, second{0};
        forkJoin.invoke(
            split, [&] { ++first; }, [&] { ++second; });
        EXPECT_EQ(first, 1);
        EXPECT_EQ(second, 1);
    }
    ForkJoin forkJoin(2);
    EXPECT_THROW(forkJoin.invoke(
                     true, [] { throw std::runtime_error("first"); }, [] {}),
                 std::runtime_error);
}

}  // namespace
}  // namespace vkrt
