// Memory known before it is spent (issue 14): the host and device estimates, renders refused with the figures
// (exit 2) before anything is allocated, images rendered in tiles when only the accumulation does not fit,
// and a lost device (exit 1) keeping the samples the host had copied.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/host_memory.h"
#include "app/huge_page_heap.h"
#include "common/memory_need.h"
#include "image/image_io.h"
#include "support/huge_pages.h"
#include "support/json_file.h"
#include "support/run_command.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::readJson;

std::string cornell() {
    return "--scene '" + (test::sourceDir() / "scenes/cornell.gltf").string() + "'";
}

TEST(MemoryNeed, FormatsBytesInBinaryUnits) {
    EXPECT_EQ(formatBytes(0), "0 B");
    EXPECT_EQ(formatBytes(1023), "1023 B");
    EXPECT_EQ(formatBytes(1024), "1.00 KiB");
    EXPECT_EQ(formatBytes(1536 << 20), "1.50 GiB");
    EXPECT_EQ(formatBytes(100ull << 20), "100 MiB");
    EXPECT_EQ(formatBytes(uint64_t{3} << 50), "3.00 PiB");
}

TEST(MemoryNeed, DescribesTheLargestPartsFirst) {
    MemoryNeed need;
    need.add("small", 1024);
    need.add("none", 0);  // left out
    need.add("large", 3 << 20);
    EXPECT_EQ(need.total(), (3u << 20) + 1024u);
    EXPECT_EQ(need.parts().size(), 2u);
    EXPECT_EQ(need.largest().what, "large");
    EXPECT_EQ(need.describe(), "3.00 MiB (large 3.00 MiB, small 1.00 KiB)");
}

TEST(HostMemory, EstimateGrowsWithPixelsTrianglesAndTheWayItIsRendered) {
    HostMemoryInputs in;
    in.width = 1000;
    in.height = 1000;
    in.outputPath = "x.pfm";
    auto estimate = [&] { return estimateHostMemory(in).total(); };
    const uint64_t pixelsOnly = estimate();
    EXPECT_EQ(pixelsOnly, 1000000u * (32 + 12)) << "double sums and the float image";
    in.outputPath = "x.exr";
    const uint64_t exr = estimate();
    EXPECT_GT(exr, pixelsOnly) << "the encoder's buffers";
    in.triangles = 1000000;
    const uint64_t cpu = estimate();
    EXPECT_GT(cpu, exr + 100000000u) << "a BVH build of a million triangles takes hundreds of MB";
    in.gpu = true;
    const uint64_t gpu = estimate();
    EXPECT_GT(gpu, cpu + 100000000u) << "the scene packed for the GPU";
    in.deviceInHostMemory = true;
    EXPECT_GT(estimate(), gpu + 32000000u) << "lavapipe's buffers are host memory";
    in.deviceBudgetBytes = 1000;
    EXPECT_EQ(estimate(), gpu + 1000u) << "but no more than its budget: beyond it, the image is tiled";
    in.report = true;
    EXPECT_EQ(estimate(), gpu + 1000u + 24000000u) << "the reference and checkpoint images";
    // A rank of an MPI job holds the copy of its sums it reduces, and at a checkpoint another (rank 0's
    // memory rose to 1.76 times the estimate under a report).
    in.shared = true;
    EXPECT_EQ(estimate(), gpu + 1000u + 24000000u + 2u * 32000000u) << "sums reduced at checkpoints";
    in.report = false;
    EXPECT_EQ(estimate(), gpu + 1000u + 32000000u) << "sums reduced once";
    in.shared = false;
    // Textures: packed on the host for the CPU reference; for the GPU, written into its buffers, through a
    // staging buffer unless the device's memory is the host's (and within its budget, then).
    in = HostMemoryInputs{};
    in.width = in.height = 1000;
    in.outputPath = "x.pfm";
    in.textureBytes = 100000000;
    EXPECT_EQ(estimate(), pixelsOnly + 100000000u) << "the CPU reference's packed texels";
    in.gpu = true;
    EXPECT_EQ(estimate(), pixelsOnly + 100000000u) << "a GPU's staging buffer";
    in.deviceInHostMemory = true;
    EXPECT_EQ(estimate(), pixelsOnly + 100000000u + 1000000u * 32) << "lavapipe's texel buffer and accumulation";
    // An environment map of 10^6 texels: its sampling tables (8 bytes a texel), on the GPU its packed copy
    // (16) and, on lavapipe, the device's.
    in = HostMemoryInputs{};
    in.width = in.height = 1000;
    in.outputPath = "x.pfm";
    in.environmentTexels = 1000000;
    EXPECT_EQ(estimate(), pixelsOnly + 8000000u) << "the CPU reference's tables";
    in.gpu = true;
    EXPECT_EQ(estimate(), pixelsOnly + 24000000u) << "the tables and the map packed for the GPU";
    in.deviceInHostMemory = true;
    EXPECT_EQ(estimate(), pixelsOnly + 24000000u + 16000000u + 1000000u * 32) << "and lavapipe's copy";
}

// The EXR encoder's buffers are counted whatever the case of the output's extension, as the writer reads it:
// "m.EXR" left them out, so a render refused as m.exr (needing 240 MiB of 200) was let through as m.EXR.
TEST(HostMemory, EncoderIsCountedInAnyCaseOfTheExtension) {
    HostMemoryInputs in;
    in.width = 1000;
    in.height = 1000;
    auto estimate = [&](const char* path) {
        in.outputPath = path;
        return estimateHostMemory(in).total();
    };
    const uint64_t exr = estimate("x.exr");
    EXPECT_GT(exr, estimate("x.pfm")) << "the encoder's buffers";
    for (const char* name : {"x.EXR", "x.Exr"}) EXPECT_EQ(estimate(name), exr) << name;
}

// An environment map is counted before it is decoded: a file of half a megabyte of run-length data can claim
// 4000 x 2000 texels (192 MB decoded), and took 443 MB under --max-memory 16MiB; decoded, its tables count in
// the render's estimate.
TEST(MemoryCli, EnvironmentMapsAreCountedBeforeTheyAreDecoded) {
    const auto folder = test::temporaryFolder();
    const int width = 4000, height = 2000;
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " +
                      std::to_string(width) + "\n";
    for (int y = 0; y < height; ++y) {
        hdr += std::string("\x02\x02") + static_cast<char>(width >> 8) + static_cast<char>(width & 0xff);
        for (int component = 0; component < 4; ++component) {
            for (int x = 0; x < width; x += 127) {
                hdr += static_cast<char>(128 + std::min(127, width - x));
                hdr += static_cast<char>(component == 3 ? 128 : 100);  // radiance 100/256 in each channel
            }
        }
    }
    const auto map = folder / "wide.hdr";
    test::writeText(map, hdr);
    ASSERT_LT(std::filesystem::file_size(map), 600000u);
    for (const char* device : {"cpu", "gpu"}) {
        const auto out = folder / (std::string(device) + ".pfm");
        const test::CommandResult r = test::runVkrt(
            cornell() + " --device " + device + " --width 8 --height 8 --spp 1 --environment '" +
            map.string() + "' --max-memory 64MiB --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_NE(
            r.output.find("--environment: " + map.string() + ": decoding its 8000000 texels needs about"),
            std::string::npos)
            << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    const auto stats = folder / "stats.json";
    const test::CommandResult r = test::runVkrt(
        cornell() + " --device cpu --width 8 --height 8 --spp 1 --environment '" + map.string() +
        "' --out '" + (folder / "x.pfm").string() + "' --stats '" + stats.string() + "' --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GE(readJson(stats)["memory"]["host_estimate_bytes"].get<double>(), 8.0 * width * height);
}

// Parsing a glTF's JSON takes about 20 times its text, counted before it is parsed: a document of 100,000
// lights' nodes (28 MB) peaked at 0.8 GB with --max-memory 100M and rendered, exit 0. Here 40,000 named nodes
// (about 2.5 MB of JSON) are refused under 32 MiB on both devices, in one line, with nothing written, and
// render without the limit.
TEST(MemoryCli, JsonIsCountedBeforeItIsParsed) {
    const auto folder = test::temporaryFolder();
    nlohmann::json document = {{"asset", {{"version", "2.0"}}}, {"scene", 0}};
    nlohmann::json nodes = nlohmann::json::array(), roots = nlohmann::json::array();
    for (int i = 0; i < 40000; ++i) {
        nodes.push_back(
            {{"name", "an empty node, number " + std::to_string(i)}, {"translation", {i, 0.5, -i}}});
        roots.push_back(i);
    }
    document["nodes"] = nodes;
    document["scenes"] = {{{"nodes", roots}}};
    const auto scene = folder / "nodes.gltf";
    test::writeText(scene, document.dump());
    ASSERT_GT(std::filesystem::file_size(scene), 2000000u);
    for (const char* device : {"cpu", "gpu"}) {
        const auto out = folder / (std::string(device) + ".pfm");
        const test::CommandResult r =
            test::runVkrt("--scene '" + scene.string() + "' --device " + device +
                          " --width 4 --height 4 --spp 1 --max-memory 32MiB --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_NE(r.output.find(scene.string() + ": parsing its 2."), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("of JSON structure takes about"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("and 32.0 MiB is available (--max-memory)"), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    const test::CommandResult r = test::runVkrt(
        "--scene '" + scene.string() + "' --device cpu --width 4 --height 4 --spp 1 --quiet --out '" +
        (folder / "x.pfm").string() + "'");
    EXPECT_EQ(r.exitCode, 0) << r.output;
}

TEST(HostMemory, AvailableMemoryIsReadFromTheSystem) {
    const HostMemory memory = availableHostMemory();
    EXPECT_GT(memory.bytes, 0u);
    EXPECT_FALSE(memory.source.empty());
    EXPECT_NO_THROW(checkHostMemory(MemoryNeed{}, memory));
    MemoryNeed need;
    need.add("image", 5 << 20);
    try {
        checkHostMemory(need, HostMemory{4 << 20, "--max-memory"});
        FAIL() << "5 MiB does not fit in 4";
    } catch (const MemoryError& e) {
        EXPECT_STREQ(e.what(),
                     "the render needs about 5.00 MiB (image 5.00 MiB) of host memory, and 4.00 MiB is "
                     "available (--max-memory)");
    }
}

// Each refusal happens before the BVH build and the render: a 16384 x 16384, 4096-spp render would take
// hours.
TEST(MemoryCli, HostMemoryTooSmallIsRefusedAtOnceWithTheFigures) {
    const auto folder = test::temporaryFolder();
    for (const char* device : {"cpu", "gpu"}) {
        const auto out = folder / (std::string(device) + ".pfm");
        const test::CommandResult r =
            test::runVkrt(cornell() + " --device " + device +
                          " --width 16384 --height 16384 --spp 4096 --max-memory 1GiB "
                          "--out '" +
                          out.string() + "'");
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_NE(r.output.find("of host memory, and 1.00 GiB is available (--max-memory)"),
                  std::string::npos)
            << r.output;
        EXPECT_NE(r.output.find("image sums 8.00 GiB"), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

TEST(MemoryCli, SceneTooLargeForTheDeviceIsRefusedWithTheFigures) {
    const auto folder = test::temporaryFolder();
    const auto out = folder / "x.png";
    const test::CommandResult r = test::runVkrt(
        cornell() + " --width 16384 --height 16384 --spp 4096 --max-device-memory 2KiB --out '" +
        out.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("needs more device memory than it has: the scene"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("for one row of the image, against 2.00 KiB (--max-device-memory)"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(MemoryCli, SizesAreCheckedAsTheyAreParsed) {
    for (const char* size : {"12XB", "-1GiB", "0", "1e30GiB", "GiB"}) {
        const test::CommandResult r = test::runVkrt(cornell() + " --max-memory " + size);
        EXPECT_EQ(r.exitCode, 2) << size << ": " << r.output;
        EXPECT_NE(r.output.find("--max-memory"), std::string::npos) << r.output;
    }
}

// The host estimate against what the process really takes: the growth of its peak resident memory from a
// tiny render to a 1024 x 1024 one, on each device. The estimate may be generous, not short. A process's peak
// varies from run to run by what the driver happens to allocate (lavapipe's varied by 30 MB between two runs
// of the tiny render), never below what the render needs: each size's peak is the least of three runs. On a GPU
// with its own memory the driver's own allocations move the difference more than the bound allows (on an H200 it
// was 15 MB against the 46 estimated in one run, within the bound in another, the cause not found): there the
// estimate is only checked to cover what the process takes.
TEST(MemoryCli, HostEstimateCoversWhatTheRenderTakes) {
    const auto folder = test::temporaryFolder();
    for (const char* device : {"cpu", "gpu"}) {
        bool deviceInHostMemory = true;
        double estimate[2] = {0.0, 0.0}, peak[2] = {0.0, 0.0};
        const int widths[2] = {16, 1024};
        for (int i = 0; i < 2; ++i) {
            for (int run = 0; run < 3; ++run) {
                const auto json = folder / ("stats-" + std::to_string(i) + ".json");
                const test::CommandResult r = test::runVkrt(
                    cornell() + " --device " + device + " --integrator whitted --spp 1 --width " +
                    std::to_string(widths[i]) + " --out '" + (folder / "x.png").string() + "' --stats '" +
                    json.string() + "' --quiet");
                ASSERT_EQ(r.exitCode, 0) << r.output;
                const nlohmann::json stats = readJson(json), memory = stats["memory"];
                if (std::string(device) == "gpu") deviceInHostMemory = stats["device_type"] == "CPU";
                estimate[i] = memory["host_estimate_bytes"].get<double>();
                const double bytes = memory["host_peak_bytes"].get<double>();
                peak[i] = run == 0 ? bytes : std::min(peak[i], bytes);
            }
        }
        const double estimated = estimate[1] - estimate[0];
        const double measured = peak[1] - peak[0];
        EXPECT_GE(estimated, 0.9 * measured) << device;
        if (deviceInHostMemory) {
            EXPECT_LE(estimated, 1.6 * measured) << device;
        }
    }
}

// vkrt's heap on transparent huge pages (app/huge_page_heap.h), where the kernel gives them to memory advised
// for them ("madvise", Debian's default): lavapipe's pipeline creation alone fills megabytes of it. Where the
// kernel gives them to all memory, or to none, the stat cannot tell the heap's advice from the kernel's.
TEST(MemoryCli, HeapIsOnHugePages) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer's allocator stands in front of glibc's";
#endif
    if (!test::hugePagesOnRequest()) GTEST_SKIP() << "transparent huge pages are not given on request";
    if (!test::hugePagesGivenNow()) GTEST_SKIP() << "the kernel gives no huge pages now";
    const auto folder = test::temporaryFolder();
    const auto json = folder / "stats.json";
    const test::CommandResult r =
        test::runVkrt(cornell() + " --device gpu --integrator whitted --spp 1 --width 64 --out '" +
                      (folder / "x.png").string() + "' --stats '" + json.string() + "' --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GE(readJson(json)["memory"]["host_huge_page_bytes"].get<uint64_t>(), uint64_t{2} << 20);
}

// Every thread allocates from the main thread's heap, on huge pages (huge_page_heap.h): a thread's arena of
// its own would be on 4 KiB pages (the Vulkan context, made on a thread of its own, cost 1,600 more page
// faults so). In a child process, as in vkrt, where the heap is set up before any thread exists (glibc hands
// a new thread an earlier thread's arena), and so that this process's malloc settings stay as they were.
TEST(HugePageHeap, ThreadsAllocateFromTheHeapOnHugePages) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer's allocator stands in front of glibc's";
#endif
    if (!test::hugePagesOnRequest()) GTEST_SKIP() << "transparent huge pages are not given on request";
    constexpr size_t kBytes = size_t{16} << 20;  // below the 32 MiB from which blocks are mapped on their own
    constexpr int kNoHugePagesNow = 77;
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        if (!test::hugePagesGivenNow()) _exit(kNoHugePagesNow);
        useHugePageHeap();
        char* block = nullptr;
        std::thread([&] {
            block = static_cast<char*>(std::malloc(kBytes));
            if (block) std::memset(block, 1, kBytes);
        }).join();
        const uintptr_t begin = reinterpret_cast<uintptr_t>(block);
        const uint64_t huge = block ? test::hugePageBytesIn(begin, begin + kBytes) : 0;
        std::fprintf(stderr, "a thread's 16 MiB block: %llu bytes on huge pages\n",
                     static_cast<unsigned long long>(huge));
        _exit(huge >= kBytes - (size_t{4} << 20) ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    if (WEXITSTATUS(status) == kNoHugePagesNow) GTEST_SKIP() << "the kernel gives no huge pages now";
    EXPECT_EQ(WEXITSTATUS(status), 0)
        << "the thread's block is not on huge pages (see the child's line above)";
}

// A device that offers room for the scene and one row: one-row tiles of one dispatch each at 1 spp, so the
// device lost at dispatch 5 has rendered rows 0 to 3, each copied to the host when the next tile began.
TEST(MemoryCli, LostDeviceKeepsTheTilesCopiedAndExitsOne) {
    const auto folder = test::temporaryFolder();
    const auto stats = folder / "stats.json";
    const std::string common = cornell() + " --width 32 --height 32 --spp 1 --stats '" + stats.string() + "'";
    ASSERT_EQ(test::runVkrt(common + " --out '" + (folder / "whole.pfm").string() + "'").exitCode, 0);
    const uint64_t sceneBytes =
        readJson(stats)["memory"]["device_estimate_bytes"].get<uint64_t>() - 32 * 32 * 32;
    const std::string oneRowTiles = " --max-device-memory " + std::to_string(sceneBytes + 32 * 32);

    const auto out = folder / "kept.pfm";
    const test::CommandResult r =
        test::runCommand("VKRT_VALIDATE=1 VKRT_SIMULATE_DEVICE_LOSS=5 '" + std::string(VKRT_BINARY) + "' " +
                         common + oneRowTiles + " --out '" + out.string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(
        r.output.find("vkrt: error: the device was lost (simulated at dispatch 5); wrote the samples done "
                      "(0 to 1 per pixel)"),
        std::string::npos)
        << r.output;
    const nlohmann::json s = readJson(stats);
    EXPECT_TRUE(s["device_lost"].get<bool>());
    EXPECT_EQ(s["memory"]["tiles"].get<int>(), 32);
    EXPECT_EQ(s["spp"].get<int>(), 0);
    EXPECT_EQ(s["spp_max"].get<int>(), 1);
    ASSERT_TRUE(std::filesystem::exists(out)) << r.output;
    const Image kept = readImage(out.string()), whole = readImage((folder / "whole.pfm").string());
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            if (y < 4)
                ASSERT_EQ(kept.at(x, y), whole.at(x, y)) << x << ", " << y;
            else
                ASSERT_EQ(kept.at(x, y), glm::vec3(0.0f)) << x << ", " << y;
        }
    }
}

// The error report of a render whose device is lost is written too, with the checkpoints taken before the
// loss (it was dropped, and an earlier run's stayed beside the new image).
TEST(MemoryCli, LostDeviceWritesTheReportsCheckpoints) {
    const auto folder = test::temporaryFolder();
    const auto reference = folder / "reference.pfm";
    ASSERT_EQ(test::runVkrt(cornell() + " --device cpu --width 40 --spp 4 --out '" + reference.string() + "'")
                  .exitCode,
              0);
    const auto report = folder / "report.json";
    test::writeText(report, "an earlier run's");
    const test::CommandResult r =
        test::runCommand("VKRT_SIMULATE_DEVICE_LOSS=30 '" + std::string(VKRT_BINARY) + "' " + cornell() +
                         " --width 40 --spp 256 --out '" + (folder / "x.pfm").string() + "' --reference '" +
                         reference.string() + "' --report '" + report.string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("and the checkpoints before it to " + report.string()), std::string::npos)
        << r.output;
    const nlohmann::json written = readJson(report);
    ASSERT_GE(written["checkpoints"].size(), 1u) << written.dump();
    EXPECT_EQ(written["checkpoints"][0]["samples"], 1);
}

TEST(MemoryCli, LostDeviceBeforeAnySampleWritesNothing) {
    const auto folder = test::temporaryFolder();
    const auto out = folder / "x.png";
    const auto stats = folder / "x.json";
    test::writeText(stats, "an earlier run's");
    const test::CommandResult r = test::runCommand(
        "VKRT_VALIDATE=1 VKRT_SIMULATE_DEVICE_LOSS=1 '" + std::string(VKRT_BINARY) + "' " + cornell() +
        " --width 32 --spp 4 --out '" + out.string() + "' --stats '" + stats.string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(
        r.output.find("the device was lost (simulated at dispatch 1); no samples were kept, nothing written"),
        std::string::npos)
        << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_EQ(test::readText(stats), "an earlier run's");  // the stats are not written either
}

}  // namespace
}  // namespace vkrt
