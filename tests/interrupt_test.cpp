// Renders that end early keep their work: SIGINT, SIGTERM and SIGHUP end the render after the dispatch or
// pixel in flight and write the image of the samples done (exit 128 + signal); a second signal ends vkrt at
// once; a time limit can end a render part way through its first pass. Each render asked for here would take
// hours if it did not stop, so a stop that failed would time the test out.
#include <signal.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/json_file.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::readJson;

struct Interrupted {
    test::CommandResult command;  // the shell's output ends with "exit=N", vkrt's exit code
    int exitCode = -1;
};

// A background job of a shell without job control (`sh -c "... &"`, as these tests run vkrt) starts with
// SIGINT ignored, and vkrt leaves it so (SigintIgnoredAtTheStartStaysIgnored); a test that sends SIGINT to
// one starts it with the default action, as an interactive shell's job has.
const std::string kSigintHeard = "env --default-signal=INT ";

// Starts vkrt in the background, sends `signals` (e.g. "INT", or "INT INT") `after` seconds, `gap` seconds
// apart, and waits for it.
Interrupted interrupt(const std::string& arguments, const std::string& signals, double gap = 0.05,
                      double after = 3.0) {
    const std::string script = kSigintHeard + "VKRT_VALIDATE=1 '" + std::string(VKRT_BINARY) + "' " +
                               arguments + " & pid=$!; sleep " + std::to_string(after) + "; for s in " +
                               signals + "; do kill -$s $pid; sleep " + std::to_string(gap) +
                               "; done; wait $pid; echo \"exit=$?\"";
    Interrupted result;
    result.command = test::runCommand("bash -c '" + [&] {
        std::string quoted;
        for (char c : script) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return quoted;
    }() + "'");
    const size_t at = result.command.output.rfind("exit=");
    if (at != std::string::npos) result.exitCode = std::stoi(result.command.output.substr(at + 5));
    return result;
}

std::string scene() { return "--scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() + "'"; }

// A scene of nothing but the background, written into `folder`: a pass of millions of pixels takes a second
// or two, so a signal 3 s in finds every pixel with a sample, and averaging and writing the image takes
// longer.
std::string backgroundOnly(const std::filesystem::path& folder) {
    const auto file = folder / "background.gltf";
    test::writeText(file, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"camera": 0, "translation": [0, 0, 4]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}]})");
    return "--scene '" + file.string() + "'";
}

// `signals`, `gap` s apart from `after` s on, sent to a CPU render of the background alone, `size` pixels
// square, are one request: the samples done are written, and vkrt exits `exitCode`.
void expectOneRequest(int size, const std::string& signals, double gap, double after, int exitCode) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "kept.exr";
    const std::string side = std::to_string(size);
    const Interrupted run =
        interrupt(backgroundOnly(folder) + " --device cpu --width " + side + " --height " + side +
                      " --spp 1000000 --out '" + image.string() + "'",
                  signals, gap, after);
    EXPECT_EQ(run.exitCode, exitCode) << run.command.output;
    EXPECT_NE(run.command.output.find("interrupted: wrote"), std::string::npos) << run.command.output;
    EXPECT_TRUE(std::filesystem::exists(image)) << run.command.output;
}

void expectKeptWork(const std::string& device, const std::string& signal, int exitCode) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "kept.exr";
    const auto stats = folder / "stats.json";
    const Interrupted run = interrupt(scene() + " --device " + device + " --width 64 --height 64 --spp 1000000 --out '" +
                                          image.string() + "' --stats '" + stats.string() + "'",
                                      signal);
    EXPECT_EQ(run.exitCode, exitCode) << run.command.output;
    EXPECT_NE(run.command.output.find("interrupted: wrote"), std::string::npos) << run.command.output;
    ASSERT_TRUE(std::filesystem::exists(image)) << run.command.output;
    const nlohmann::json s = readJson(stats);
    EXPECT_TRUE(s["interrupted"].get<bool>());
    EXPECT_GE(s["spp_max"].get<int>(), 1) << "samples were rendered in 3 s";
    EXPECT_LT(s["spp"].get<int>(), 1000000);
    EXPECT_LE(s["spp_max"].get<int>() - s["spp"].get<int>(), 64) << "passes of at most 64 samples";
}

TEST(Interrupt, SigintOnTheCpuWritesTheSamplesDone) { expectKeptWork("cpu", "INT", 130); }

TEST(Interrupt, SigtermOnTheGpuWritesTheSamplesDone) { expectKeptWork("gpu", "TERM", 143); }

// Whether this process, and so vkrt started from it, ignores hang-ups (run under nohup): vkrt then leaves
// them ignored, and a test that hangs up on it has nothing to test.
bool hangUpsIgnored() {
    struct sigaction hangUp {};
    return sigaction(SIGHUP, nullptr, &hangUp) == 0 && hangUp.sa_handler == SIG_IGN;
}

// A hang-up (the terminal closed) stops the render as SIGTERM does; it ended vkrt at once, writing nothing,
// or leaving a temporary file half written.
TEST(Interrupt, SighupOnTheCpuWritesTheSamplesDone) {
    if (hangUpsIgnored()) GTEST_SKIP() << "hang-ups are ignored here (nohup)";
    expectKeptWork("cpu", "HUP", 129);
}

// The hang-up comes twice as a terminal goes (the shell passes it on, and the system sends it when the shell
// has exited): the second is the same request, and the samples done are still written. The second comes while
// the 4096 x 4096 image is being averaged and written (see SecondSigintEndsAtOnceWithoutWriting). The first
// comes 10 s in: with two test processes and a build on the two cores, the first pass over the 16.8 million
// pixels was not done at 6 s, and nothing was written.
TEST(Interrupt, SecondSighupIsTheSameRequest) {
    if (hangUpsIgnored()) GTEST_SKIP() << "hang-ups are ignored here (nohup)";
    expectOneRequest(4096, "HUP HUP", 0.3, 10.0, 129);
}

// Under nohup (hang-ups ignored when vkrt starts) a hang-up stays ignored: the render goes on until the
// SIGTERM after it.
TEST(Interrupt, SighupIgnoredAtTheStartStaysIgnored) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "kept.exr";
    const test::CommandResult run = test::runCommand(
        "trap '' HUP; '" + std::string(VKRT_BINARY) + "' " + scene() +
        " --device cpu --width 64 --height 64 --spp 1000000 --out '" + image.string() +
        "' 2>&1 & pid=$!; sleep 2; kill -HUP $pid; sleep 1; kill -TERM $pid; wait $pid; echo \"exit=$?\"");
    EXPECT_NE(run.output.find("exit=143"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("interrupted: wrote"), std::string::npos) << run.output;
    EXPECT_TRUE(std::filesystem::exists(image)) << run.output;
}

// In a script's background job (a shell without job control), where Ctrl-C is ignored so that it ends the
// script's foreground command alone, vkrt leaves it ignored: the render goes on until the SIGTERM after it.
// vkrt stopped, writing the samples done, where the script went on expecting the whole render.
TEST(Interrupt, SigintIgnoredAtTheStartStaysIgnored) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "kept.exr";
    const test::CommandResult run = test::runCommand(
        "trap '' INT; '" + std::string(VKRT_BINARY) + "' " + scene() +
        " --device cpu --width 64 --height 64 --spp 1000000 --out '" + image.string() +
        "' 2>&1 & pid=$!; sleep 2; kill -INT $pid; sleep 1; kill -TERM $pid; wait $pid; echo \"exit=$?\"");
    EXPECT_NE(run.output.find("exit=143"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("interrupted: wrote"), std::string::npos) << run.output;
    EXPECT_TRUE(std::filesystem::exists(image)) << run.output;
}

// The first SIGINT stops a 4096 x 4096 render, whose image then takes seconds to average and write; the
// second, 0.3 s later, ends vkrt there and then, leaving no file, not even the temporary one. The first comes
// 6 s in: the first pass takes 1 to 2 s on 2 cores, and more than 3 s on a machine busy with other work.
TEST(Interrupt, SecondSigintEndsAtOnceWithoutWriting) {
    const auto folder = test::temporaryFolder();
    const std::string background = backgroundOnly(folder);
    const auto image = folder / "never.exr";
    const Interrupted run = interrupt(
        background + " --device cpu --width 4096 --height 4096 --spp 1000000 --out '" + image.string() + "'",
        "INT INT", 0.3, 6.0);
    EXPECT_EQ(run.exitCode, 130) << run.command.output;  // killed by SIGINT, as the shell reports it
    EXPECT_EQ(run.command.output.find("wrote"), std::string::npos) << run.command.output;
    EXPECT_EQ(run.command.output.find("before every pixel"), std::string::npos)
        << "the first signal came after the first pass: the image was being written\n"
        << run.command.output;
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1) << "nothing but the scene";
}

// Loading does not look for a stop, and may never end: a first signal while loading ends vkrt if the render
// has not begun 3 s later. The scene is a named pipe no one writes to, so loading it never ends; vkrt that
// waited for it would be killed 10 s later (exit 137).
TEST(Interrupt, SignalWhileLoadingEndsWhatNeverLoads) {
    const auto folder = test::temporaryFolder();
    const std::string pipe = (folder / "scene.gltf").string();
    const test::CommandResult run =
        test::runCommand("mkfifo '" + pipe + "' && { '" + std::string(VKRT_BINARY) + "' --scene '" + pipe +
                         "' --out '" + (folder / "x.png").string() +
                         "' & pid=$!; sleep 1; kill -TERM $pid; for i in $(seq 100); do kill -0 $pid "
                         "2>/dev/null || break; sleep 0.1; "
                         "done; kill -KILL $pid 2>/dev/null; wait $pid; echo \"exit=$?\"; }");
    EXPECT_NE(run.output.find("exit=143"), std::string::npos) << run.output;  // ended by SIGTERM
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1) << "nothing but the pipe";
}

// A time limit ends the render inside its first pass (one sample of 16M pixels, many seconds on a few cores),
// with each pixel averaged over its own samples: some have one, the rest none. The limit is the tracing's:
// the image's 512 MiB of sums took 1.7 s to allocate, and with them inside the limit a 1 s render traced one
// pixel (CPU) or its first dispatch's row (GPU); a second of tracing gets far more than a row.
TEST(Interrupt, TimeLimitEndsInsideAPass) {
    for (const char* device : {"cpu", "gpu"}) {
        SCOPED_TRACE(device);
        const auto folder = test::temporaryFolder();
        const auto stats = folder / "stats.json";
        const test::CommandResult run = test::runVkrt(
            scene() + " --device " + device + " --width 4096 --height 4096 --spp 64 --time-limit 1 --out '" +
            (folder / "x.exr").string() + "' --stats '" + stats.string() + "'");
        EXPECT_EQ(run.exitCode, 0) << run.output;
        const nlohmann::json s = readJson(stats);
        EXPECT_TRUE(s["stopped_by_time_limit"].get<bool>());
        EXPECT_FALSE(s["interrupted"].get<bool>());
        EXPECT_EQ(s["spp"].get<int>(), 0);
        EXPECT_EQ(s["spp_max"].get<int>(), 1);
        EXPECT_GT(s["rays"]["primary"].get<uint64_t>(), 4u * 4096u);
        EXPECT_NE(run.output.find("before every pixel had a sample"), std::string::npos) << run.output;
    }
}

// timeout(1) sends its signal to vkrt and then to its process group: one request, twice, from one sender. A
// repeat from the same sender within 0.1 s is that request (it ended vkrt at once, writing nothing, in a
// third of `timeout -s INT` runs); a second Ctrl-C, or a repeat later, still ends it at once.
TEST(Interrupt, RepeatFromOneSenderIsOneRequest) {
    // 2048 x 2048: its image takes a few tenths of a second to average and write, so the repeat comes first.
    expectOneRequest(2048, "INT INT", 0.02, 3.0, 130);
}

// Once its image is written, a stopped vkrt ends by the signal itself rather than exiting 130: a shell that
// runs it in a loop or a script sees a command killed by SIGINT and stops too (one that sees an exit takes
// the signal as handled and goes on to the next command).
TEST(Interrupt, StoppedRenderEndsByItsSignal) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "kept.exr";
    const std::string script =
        "import signal, subprocess, sys, time\n"
        "p = subprocess.Popen(sys.argv[1:])\n"
        "time.sleep(3)\n"
        "p.send_signal(signal.SIGINT)\n"
        "print('returncode=%d' % p.wait())\n";
    const test::CommandResult run =
        test::runCommand("python3 -c \"" + script + "\" '" + std::string(VKRT_BINARY) + "' " + scene() +
                         " --device cpu --width 64 --height 64 --spp 1000000 --out '" + image.string() + "'");
    EXPECT_NE(run.output.find("returncode=-2"), std::string::npos) << run.output;  // killed by SIGINT
    EXPECT_NE(run.output.find("interrupted: wrote"), std::string::npos) << run.output;
    EXPECT_TRUE(std::filesystem::exists(image)) << run.output;
}

// A signal that stops the render before every pixel has a sample (here while the shader compiles, its cache
// empty) leaves the image that stood at the output path as it was: the new one would have black holes (it
// was written, 0 to 1 samples a pixel, over the old one).
TEST(Interrupt, StopBeforeEveryPixelHasASampleWritesNothing) {
    const auto folder = test::temporaryFolder();
    const auto image = folder / "old.pfm";
    test::writeText(image, "an earlier render");
    const test::CommandResult run =
        test::runCommand(kSigintHeard + "VKRT_SHADER_CACHE='" + (folder / "cache").string() + "' '" +
                         std::string(VKRT_BINARY) + "' " + scene() +
                         " --device gpu --width 1024 --height 1024 --spp 1000000 --out '" + image.string() +
                         "' 2>&1 & pid=$!; sleep 0.5; kill -INT $pid; wait $pid; echo \"exit=$?\"");
    EXPECT_NE(run.output.find("exit=130"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("vkrt: interrupted before every pixel had a sample; nothing written"),
              std::string::npos)
        << run.output;
    EXPECT_EQ(test::readText(image), "an earlier render");
}

}  // namespace
}  // namespace vkrt
