// One render shared by the ranks of an MPI job (host/app/shared_render.h): the ranks split the sample
// indices, so N ranks make the image one process makes with the same seed, to rounding, on either device and
// with a CPU rank beside a GPU rank; rank 0 alone writes the image and the stats; a failing rank ends the job
// with a non-zero exit and no file. The tests run `mpirun` and skip, saying so, without it or an MPI build.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/mpi_job.h"
#include "image/image_io.h"
#include "image/image_metrics.h"
#include "support/json_file.h"
#include "support/reference_comparison.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::readJson;

// The launcher's command line: Open MPI refuses root without its two variables and more ranks than cores
// without --oversubscribe (this suite runs on 2 cores beside other tests).
std::string mpirun() {
    static const std::string command = [] {
        if (test::runCommand("command -v mpirun").exitCode != 0) return std::string();
        const bool openMpi =
            test::runCommand("mpirun --version").output.find("Open MPI") != std::string::npos;
        return openMpi
                   ? std::string(
                         "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe")
                   : std::string("mpirun");
    }();
    return command;
}

#define SKIP_WITHOUT_MPI()                                                                           \
    do {                                                                                             \
        if (!MpiJob::built()) GTEST_SKIP() << "vkrt was built without MPI (Debian: libopenmpi-dev)"; \
        if (mpirun().empty()) GTEST_SKIP() << "mpirun is not installed (Debian: openmpi-bin)";       \
    } while (0)

std::string vkrt() {
    return std::string("'") + VKRT_BINARY + "'";
}

// A small render of the Cornell box; the CPU on one thread per rank (the machine's cores are few).
std::string render(const std::string& device, const std::filesystem::path& out, int spp = 24) {
    return "--scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() + "' --device " + device +
           " --width 48 --height 48 --spp " + std::to_string(spp) + " --seed 7 --threads 1 --out '" +
           out.string() + "'";
}

// The same render in one process and in two ranks on `device`: equal to float rounding.
void expectTwoRanksEqualOneProcess(const std::string& device) {
    const auto folder = test::temporaryFolder();
    const test::CommandResult one = test::runVkrt(render(device, folder / "one.pfm") + " --quiet");
    ASSERT_EQ(one.exitCode, 0) << one.output;
    const test::CommandResult two = test::runCommand("VKRT_VALIDATE=1 " + mpirun() + " -np 2 " + vkrt() +
                                                     " " + render(device, folder / "two.pfm") + " --stats '" +
                                                     (folder / "two.json").string() + "'");
    ASSERT_EQ(two.exitCode, 0) << two.output;
    const Image a = readImage((folder / "one.pfm").string());
    const Image b = readImage((folder / "two.pfm").string());
    const ImageDifference d = compareImages(b, a, 1e-5, 1e-6);
    EXPECT_EQ(d.fractionOff, 0.0) << "two ranks must render the samples one process does";
    if (d.fractionOff > 0.0) test::saveForInspection(b, a, "mpi-two-ranks-" + device);

    // Rank 0 wrote the stats of the whole render, with each rank's share.
    const nlohmann::json stats = readJson(folder / "two.json");
    EXPECT_EQ(stats["ranks"], 2);
    EXPECT_EQ(stats["spp"], 24);
    ASSERT_EQ(stats["per_rank"].size(), 2u);
    uint64_t samples = 0, primary = 0;
    for (const nlohmann::json& rank : stats["per_rank"]) {
        EXPECT_EQ(rank["device"], device);
        EXPECT_GT(rank["spp"].get<uint64_t>(), 0u) << "every rank takes at least one batch";
        samples += rank["spp"].get<uint64_t>();
        primary += rank["rays"]["primary"].get<uint64_t>();
    }
    EXPECT_EQ(samples, 24u) << "the ranks' samples are disjoint and cover the render";
    EXPECT_EQ(primary, 48u * 48u * 24u);
    EXPECT_EQ(stats["rays"]["primary"], primary);
    // Only rank 0 speaks.
    EXPECT_EQ(two.output.find("wrote"), two.output.rfind("wrote")) << two.output;
}

TEST(Mpi, TwoCpuRanksEqualOneProcess) {
    SKIP_WITHOUT_MPI();
    expectTwoRanksEqualOneProcess("cpu");
}

TEST(Mpi, TwoGpuRanksEqualOneProcess) {
    SKIP_WITHOUT_MPI();
    expectTwoRanksEqualOneProcess("gpu");
}

// MPMD: a CPU rank beside a GPU rank. Each sample is rendered by one of them, so the image matches the CPU
// reference as the GPU's own renders do (the conformance thresholds), and both ranks did part of it.
TEST(Mpi, CpuRankBesideGpuRank) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult one = test::runVkrt(render("cpu", folder / "one.pfm") + " --quiet");
    ASSERT_EQ(one.exitCode, 0) << one.output;
    const std::string stats = " --stats '" + (folder / "mixed.json").string() + "'";
    const test::CommandResult mixed = test::runCommand(
        "VKRT_VALIDATE=1 " + mpirun() + " -np 1 " + vkrt() + " " + render("cpu", folder / "mixed.pfm") +
        stats + " : -np 1 " + vkrt() + " " + render("gpu", folder / "mixed.pfm") + stats);
    ASSERT_EQ(mixed.exitCode, 0) << mixed.output;
    const Image reference = readImage((folder / "one.pfm").string());
    const Image image = readImage((folder / "mixed.pfm").string());
    const ImageDifference d = test::compareWithReference(image, reference);
    EXPECT_TRUE(test::withinReferenceThresholds(d))
        << d.fractionOff * 100 << "% of pixels off, mean relative error " << d.meanRelativeError;

    const nlohmann::json s = readJson(folder / "mixed.json");
    EXPECT_EQ(s["ranks"], 2);
    EXPECT_EQ(s["device"], "mixed");
    ASSERT_EQ(s["per_rank"].size(), 2u);
    EXPECT_EQ(s["per_rank"][0]["device"], "cpu");
    EXPECT_EQ(s["per_rank"][0]["device_name"], "cpu reference");
    EXPECT_EQ(s["per_rank"][1]["device"], "gpu");
    EXPECT_GT(s["per_rank"][0]["spp"].get<int>(), 0);
    EXPECT_GT(s["per_rank"][1]["spp"].get<int>(), 0);
    EXPECT_EQ(s["per_rank"][0]["spp"].get<int>() + s["per_rank"][1]["spp"].get<int>(), 24);
}

// A rank that cannot start (a device that does not exist) ends the whole job, non-zero, and nothing is
// written: rank 0 writes only at the end.
TEST(Mpi, FailingRankEndsTheJobWithoutOutput) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const auto out = folder / "never.png";
    const test::CommandResult job =
        test::runCommand(mpirun() + " -np 1 " + vkrt() + " " + render("cpu", out, 100000) + " : -np 1 " +
                         vkrt() + " " + render("gpu", out, 100000) + " --device-index 99");
    EXPECT_NE(job.exitCode, 0) << job.output;
    EXPECT_NE(job.output.find("vkrt: rank 1: error: --device-index 99"), std::string::npos) << job.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// Ranks given different renders (here sizes) would add up nonsense: bad usage, exit 2, nothing written.
TEST(Mpi, RanksMustRenderTheSameImage) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const auto out = folder / "never.png";
    const test::CommandResult job =
        test::runCommand(mpirun() + " -np 1 " + vkrt() + " " + render("cpu", out) + " : -np 1 " + vkrt() +
                         " " + render("cpu", out, 25));
    EXPECT_EQ(job.exitCode, 2) << job.output;
    EXPECT_NE(job.output.find("every rank needs the same scene and render options"), std::string::npos)
        << job.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    // Any option that changes the image, not only the size: light samples, filter, background, aperture.
    for (const char* option :
         {"--light-samples 4", "--filter gaussian", "--background 5", "--aperture 0.1"}) {
        const test::CommandResult other =
            test::runCommand(mpirun() + " -np 1 " + vkrt() + " " + render("cpu", out) + " : -np 1 " + vkrt() +
                             " " + render("cpu", out) + " " + option);
        EXPECT_EQ(other.exitCode, 2) << option << "\n" << other.output;
        EXPECT_NE(other.output.find("every rank needs the same scene and render options"), std::string::npos)
            << other.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << option;
    }
    // And the animation asked for (ranks playing different clips of one file made one ghosted image).
    const std::string deform = "--scene '" + (test::sourceDir() / "scenes/deform.gltf").string() +
                               "' --device cpu --width 16 --height 16 --spp 2 --out '" + out.string() + "'";
    const test::CommandResult clips =
        test::runCommand(mpirun() + " -np 1 " + vkrt() + " " + deform + " : -np 1 " + vkrt() + " " + deform +
                         " --animation motion");
    EXPECT_EQ(clips.exitCode, 2) << clips.output;
    EXPECT_NE(clips.output.find("every rank needs the same scene and render options"), std::string::npos)
        << clips.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// Rank 0's --report decides for every rank: a report asked of rank 1 alone is not rank 1's to make (it once
// mixed its reference's samples into the image), and one asked of rank 0 alone has every rank render the
// reference with it (it once hung the job).
TEST(Mpi, ReportIsRankZerosToAsk) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult one = test::runVkrt(render("cpu", folder / "one.pfm", 8) + " --quiet");
    ASSERT_EQ(one.exitCode, 0) << one.output;
    const std::string report = " --report '" + (folder / "report.json").string() + "'";
    // The report on rank 1, on rank 0, and on rank 0 with its own --report-every-ms (which set rank 0's
    // phases alone and hung the job).
    for (const std::string& rootOptions : {std::string(), report, report + " --report-every-ms 1"}) {
        const bool onRoot = !rootOptions.empty();
        const std::string out = (folder / (onRoot ? "root.pfm" : "other.pfm")).string();
        const test::CommandResult job = test::runCommand(
            "timeout 120 env " + mpirun() + " -np 1 " + vkrt() + " " + render("cpu", out, 8) + rootOptions +
            " : -np 1 " + vkrt() + " " + render("cpu", out, 8) + (onRoot ? "" : report));
        ASSERT_EQ(job.exitCode, 0) << rootOptions << "\n" << job.output;
        EXPECT_EQ(compareImages(readImage(out), readImage((folder / "one.pfm").string())).rmse, 0.0)
            << (onRoot ? "report on rank 0" : "report on rank 1");
    }
    EXPECT_TRUE(std::filesystem::exists(folder / "report.json"));
}

// --help or --list-devices given to one rank of a job prints and ends every rank, never a hang.
TEST(Mpi, ListDevicesOnOneRankEndsTheJob) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult job =
        test::runCommand("timeout 60 env " + mpirun() + " -np 1 " + vkrt() + " " +
                         render("cpu", folder / "x.png") + " : -np 1 " + vkrt() + " --list-devices");
    EXPECT_NE(job.exitCode, 124) << job.output;  // timeout's: the job hung
    EXPECT_NE(job.exitCode, 0) << job.output;    // rank 0 was asked to render and did not
    EXPECT_NE(job.output.find(", Vulkan "), std::string::npos) << job.output;  // a device of the list
    EXPECT_NE(job.output.find("given --help or --list-devices"), std::string::npos) << job.output;
    EXPECT_FALSE(std::filesystem::exists(folder / "x.png"));
}

// The stats of a job whose rank 0 is a GPU rank keep its device figures as one process does: its memory and
// tiles (they were zeros), and its rays per GPU second from its own rays (not the job's over its GPU time).
TEST(Mpi, StatsKeepRankZerosGpuFigures) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult job = test::runCommand(
        "VKRT_VALIDATE=1 " + mpirun() + " -np 2 " + vkrt() + " " + render("gpu", folder / "tiled.pfm", 8) +
        " --max-device-memory 60K --stats '" + (folder / "tiled.json").string() + "'");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    const nlohmann::json s = readJson(folder / "tiled.json");
    EXPECT_GT(s["memory"]["tiles"].get<int>(), 1) << s["memory"].dump();
    EXPECT_GT(s["memory"]["device_budget_bytes"].get<double>(), 0.0);
    const nlohmann::json& rays = s["per_rank"][0]["rays"];
    const double rank0Rays =
        rays["primary"].get<double>() + rays["shadow"].get<double>() + rays["secondary"].get<double>();
    EXPECT_NEAR(s["mrays_per_gpu_s"].get<double>(), rank0Rays / s["gpu_ms"].get<double>() / 1e3,
                1e-9 * s["mrays_per_gpu_s"].get<double>());
    // Its render time counts the renderer's set-up, as one process's does (it began after it).
    EXPECT_GE(s["render_ms"].get<double>(),
              s["setup"]["total_ms"].get<double>() + s["dispatches"]["total_ms"].get<double>());
}

// A rank whose device is lost part way ends the job too: a shared render is all or nothing.
TEST(Mpi, LostDeviceOnOneRankEndsTheJobWithoutOutput) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const auto out = folder / "never.png";
    const test::CommandResult job = test::runCommand(
        mpirun() + " -np 1 " + vkrt() + " " + render("cpu", out, 100000) +
        " : -np 1 env VKRT_SIMULATE_DEVICE_LOSS=3 " + vkrt() + " " + render("gpu", out, 100000));
    EXPECT_NE(job.exitCode, 0) << job.output;
    EXPECT_NE(job.output.find("vkrt: rank 1: error:"), std::string::npos) << job.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// --time-limit holds for every rank: a render that would take hours ends, and the image of the samples done
// is written.
TEST(Mpi, TimeLimitEndsEveryRank) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult job = test::runCommand(
        mpirun() + " -np 2 " + vkrt() + " " + render("cpu", folder / "limited.pfm", 1000000) +
        " --time-limit 1 --stats '" + (folder / "limited.json").string() + "'");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    EXPECT_TRUE(std::filesystem::exists(folder / "limited.pfm"));
    const nlohmann::json s = readJson(folder / "limited.json");
    EXPECT_TRUE(s["stopped_by_time_limit"].get<bool>());
    EXPECT_GE(s["spp"].get<int>(), 1);
    EXPECT_LT(s["spp_max"].get<int>(), 1000000);
    for (const nlohmann::json& rank : s["per_rank"]) EXPECT_LT(rank["render_ms"].get<double>(), 5000.0);

    // A time limit that passes once every sample is handed out stops nothing: the render of one pixel, whose
    // one sample the CPU finishes once begun, is whole.
    const test::CommandResult whole = test::runCommand(
        mpirun() + " -np 2 " + vkrt() + " --scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() +
        "' --device cpu --threads 1 --width 1 --height 1 --spp 1 --time-limit 0.000001 --out '" +
        (folder / "whole.pfm").string() + "' --stats '" + (folder / "whole.json").string() + "'");
    ASSERT_EQ(whole.exitCode, 0) << whole.output;
    const nlohmann::json w = readJson(folder / "whole.json");
    EXPECT_EQ(w["spp"], 1);
    EXPECT_FALSE(w["stopped_by_time_limit"].get<bool>());
}

// A job the time limit stops between checkpoints ends its report with the image rank 0 writes, as one process
// does: its error is the written image's, and its samples the fewest any pixel has.
TEST(Mpi, ReportOfAStoppedJobEndsWithTheImageWritten) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    ASSERT_EQ(test::runVkrt(render("cpu", folder / "reference.pfm", 256) + " --quiet").exitCode, 0);
    const test::CommandResult job = test::runCommand(
        mpirun() + " -np 2 " + vkrt() + " " + render("cpu", folder / "limited.pfm", 1000000) +
        " --time-limit 1 --reference '" + (folder / "reference.pfm").string() + "' --report '" +
        (folder / "limited.json").string() + "' --stats '" + (folder / "stats.json").string() + "'");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    const nlohmann::json report = readJson(folder / "limited.json");
    const nlohmann::json& last = report["checkpoints"].back();
    EXPECT_EQ(last["samples"], readJson(folder / "stats.json")["spp"]);
    const double rmse = compareImages(readImage((folder / "limited.pfm").string()),
                                      readImage((folder / "reference.pfm").string()))
                            .rmse;
    EXPECT_NEAR(last["rmse"].get<double>(), rmse, 1e-6 * rmse);
}

// A job stopped part way counts the samples every pixel has across the ranks: a sum of the ranks' fewest
// undercounted them where the pixels one rank's last batch left short are not the ones another's did (stats
// 166 beside a last checkpoint of 170), and a sum of their most overstated them. Here each of two ranks
// leaves a different one of two pixels short (shared_render_ranks.cpp): both pixels have one sample, where
// the sums said 0 to 2.
TEST(Mpi, StoppedJobCountsTheSamplesEveryPixelHas) {
    SKIP_WITHOUT_MPI();
    const test::CommandResult job =
        test::runCommand(mpirun() + " -np 2 '" + std::string(VKRT_SHARED_RENDER_RANKS) + "'");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    EXPECT_EQ(job.output, "1 1\n");
}

// The same through vkrt, where the clock cuts the batches: however they fall, the stats count what the
// report's last checkpoint does. The job runs a few times, on more threads than cores, so that rows finish
// out of order and the ranks' short pixels differ now and then (the sums disagreed in about one run of ten).
TEST(Mpi, StoppedJobsStatsAgreeWithItsReport) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    ASSERT_EQ(test::runVkrt(render("cpu", folder / "reference.pfm", 64) + " --quiet").exitCode, 0);
    const std::string job =
        mpirun() + " -np 2 " + vkrt() + " --scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() +
        "' --device cpu --width 48 --height 48 --spp 1000000 --seed 7 --threads 8 --out '" +
        (folder / "limited.pfm").string() + "' --time-limit 0.5 --reference '" +
        (folder / "reference.pfm").string() + "' --report '" + (folder / "report.json").string() +
        "' --stats '" + (folder / "stats.json").string() + "' --quiet";
    for (int run = 1; run <= 3; ++run) {
        const test::CommandResult limited = test::runCommand(job);
        ASSERT_EQ(limited.exitCode, 0) << limited.output;
        const nlohmann::json stats = readJson(folder / "stats.json");
        const nlohmann::json report = readJson(folder / "report.json");
        ASSERT_TRUE(stats["stopped_by_time_limit"].get<bool>()) << "run " << run;
        // With no sample left out, a pixel's count is the samples traced.
        ASSERT_EQ(stats["nonfinite_samples"], 0) << "run " << run;
        const uint64_t fewest = stats["spp"], most = stats["spp_max"];
        EXPECT_EQ(report["checkpoints"].back()["samples"], fewest) << "run " << run;
        EXPECT_EQ(report["spp"], fewest) << "run " << run;
        // Each rank's counts bound the job's: its fewest add up to no more, its most to no fewer.
        uint64_t ranksFewest = 0, ranksMost = 0;
        for (const nlohmann::json& rank : stats["per_rank"]) {
            ranksFewest += rank["spp"].get<uint64_t>();
            ranksMost += rank["spp_max"].get<uint64_t>();
        }
        EXPECT_LE(ranksFewest, fewest) << "run " << run;
        EXPECT_LE(fewest, most) << "run " << run;
        EXPECT_LE(most, ranksMost) << "run " << run;
        // One primary ray a sample: the pixels hold from fewest to most samples each.
        const uint64_t primary = stats["rays"]["primary"], pixels = 48 * 48;
        EXPECT_LE(fewest * pixels, primary) << "run " << run;
        EXPECT_LE(primary, most * pixels) << "run " << run;
    }
}

// Ctrl-C to mpirun: Open MPI sends the ranks SIGTERM a second later (and SIGKILL a second after that); they
// stop within their batch, and rank 0 writes the samples done as an interrupted render.
TEST(Mpi, InterruptKeepsTheSamplesDone) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const std::string job = mpirun() + " -np 2 " + vkrt() + " " +
                            render("cpu", folder / "kept.pfm", 1000000) + " --stats '" +
                            (folder / "kept.json").string() + "'";
    const test::CommandResult run = test::runCommand("bash -c \"env --default-signal=INT " + job +
                                                     " & pid=\\$!; sleep 3; kill -INT \\$pid; wait \\$pid\"");
    EXPECT_NE(run.output.find("interrupted: wrote"), std::string::npos) << run.output;
    ASSERT_TRUE(std::filesystem::exists(folder / "kept.pfm")) << run.output;
    const nlohmann::json s = readJson(folder / "kept.json");
    EXPECT_TRUE(s["interrupted"].get<bool>());
    EXPECT_GE(s["spp"].get<int>(), 1);
    EXPECT_LT(s["spp_max"].get<int>(), 1000000);
    EXPECT_EQ(s["ranks"], 2);
}

// --report across ranks: the ranks render in phases that end at the checkpoints, so every checkpoint's image
// is the one process's (the errors agree to rounding), and the reference is shared as the render is.
// A job's checkpoints count their render time from rank 0's renderer set-up on, as its stats' render_ms and
// one process's checkpoints do: the GPU's pipeline creation (setup.total_ms) was left out.
TEST(Mpi, ReportsRenderTimeCountsTheSetUp) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    ASSERT_EQ(test::runVkrt(render("cpu", folder / "reference.pfm", 64) + " --quiet").exitCode, 0);
    const test::CommandResult job = test::runCommand(
        mpirun() + " -np 2 " + vkrt() + " " + render("gpu", folder / "two.pfm", 8) + " --reference '" +
        (folder / "reference.pfm").string() + "' --report '" + (folder / "report.json").string() +
        "' --stats '" + (folder / "stats.json").string() + "' --quiet");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    const nlohmann::json report = readJson(folder / "report.json");
    const nlohmann::json stats = readJson(folder / "stats.json");
    ASSERT_EQ(report["checkpoints"].size(), 4u);  // 1, 2, 4, 8 samples
    EXPECT_GT(report["checkpoints"][0]["render_ms"].get<double>(), stats["setup"]["total_ms"].get<double>());
    EXPECT_LE(report["checkpoints"][3]["render_ms"].get<double>(), stats["render_ms"].get<double>());
}

TEST(Mpi, ReportUnderTwoRanksEqualsOneProcess) {
    SKIP_WITHOUT_MPI();
    const auto folder = test::temporaryFolder();
    const test::CommandResult one = test::runVkrt(render("cpu", folder / "one.pfm", 16) + " --report '" +
                                                  (folder / "one.json").string() + "' --quiet");
    ASSERT_EQ(one.exitCode, 0) << one.output;
    const test::CommandResult two =
        test::runCommand(mpirun() + " -np 2 " + vkrt() + " " + render("cpu", folder / "two.pfm", 16) +
                         " --report '" + (folder / "two.json").string() + "'");
    ASSERT_EQ(two.exitCode, 0) << two.output;
    const nlohmann::json a = readJson(folder / "one.json");
    const nlohmann::json b = readJson(folder / "two.json");
    EXPECT_EQ(b["ranks"], 2);
    ASSERT_EQ(a["checkpoints"].size(), 5u);  // 1, 2, 4, 8, 16 samples
    // No one GPU time belongs to a job's checkpoint: none is recorded (it read 0).
    for (const nlohmann::json& q : b["checkpoints"]) EXPECT_TRUE(q["gpu_ms"].is_null()) << q;
    ASSERT_EQ(b["checkpoints"].size(), a["checkpoints"].size());
    for (size_t i = 0; i < a["checkpoints"].size(); ++i) {
        const nlohmann::json& p = a["checkpoints"][i];
        const nlohmann::json& q = b["checkpoints"][i];
        EXPECT_EQ(p["samples"], q["samples"]);
        EXPECT_NEAR(p["rmse"].get<double>(), q["rmse"].get<double>(), 1e-9 * p["rmse"].get<double>())
            << "at " << p["samples"] << " samples";
        EXPECT_NEAR(p["relmse"].get<double>(), q["relmse"].get<double>(), 1e-9 * p["relmse"].get<double>());
    }
}

}  // namespace
}  // namespace vkrt
