// vkrt: renders a glTF 2.0 scene to an image file.
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "app/exit_codes.h"
#include "app/huge_page_heap.h"
#include "app/mpi_job.h"
#include "app/one_process_render.h"
#include "app/options.h"
#include "app/path_checks.h"
#include "app/prepared_render.h"
#include "app/rank_render.h"
#include "app/stop_signal.h"
#include "common/memory_need.h"
#include "gpu/vulkan_check.h"
#include "gpu/vulkan_context.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

// A failure: one line on stderr and the exit code. Under mpirun the line names the rank, and the whole job
// ends at once with that code (MPI_Abort): rank 0 never writes a partial result.
int fail(const MpiJob& job, int exitCode, const char* message) {
    if (job.shared()) {
        std::fprintf(stderr, "vkrt: rank %d: %s\n", job.rank(), message);
        job.abort(exitCode);
    }
    std::fprintf(stderr, "vkrt: %s\n", message);
    return exitCode;
}

// --help's text or --list-devices' list.
void printInformation(const Options& options) {
    if (options.help) {
        std::fputs(helpText().c_str(), stdout);
        return;
    }
    for (const DeviceDescription& d : listDevices()) {
        std::printf("%d: %s (%s, Vulkan %s%s%s)%s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                    d.apiVersion.c_str(), d.driver.empty() ? "" : ", ", d.driver.c_str(),
                    d.usable ? "" : " unusable: ", d.unusableBecause.c_str());
        for (const std::string& heap : d.memoryHeaps) std::printf("   %s\n", heap.c_str());
    }
}

// The render `options` ask for, by this process alone or as one rank of an MPI job; returns the exit code.
int run(Options options, const MpiJob& job) {
    // One image, one stats file and one report, from rank 0, which alone checks where they go; the others say
    // only what goes wrong.
    Options checked = options;
    if (job.rank() != 0) {
        options.quiet = true;
        checked.outputPath.clear();
        checked.statsPath.clear();
        checked.reportPath.clear();
    }
    checkPaths(checked);

    // Scene, settings, device and BVH; then the render.
    RunReport report;
    const PreparedRender prepared = prepareRender(options, job, report);
    if (job.shared()) return renderShared(job, options, prepared, report);
    return renderOneProcess(options, prepared, report);
}

}  // namespace
}  // namespace vkrt

namespace vkrt {
namespace {

// The whole run, its MPI job (if any) finalised on return; `shared` says whether it was a job of several
// ranks.
int runJob(int argc, char** argv, bool& shared) {
    // Under an MPI launcher the ranks share the render (shared_render.h); otherwise this is a job of one.
    const MpiJob job(argc, argv);
    shared = job.shared();
    try {
        Options options = parseOptions(argc, argv);
        // --help and --list-devices print and render nothing. In a job, any rank given one ends every rank
        // (each must learn it, or the others wait for it forever): it is printed once, and a rank that was
        // asked to render says why it did not.
        const bool printsOnly = options.help || options.listDevices;
        if (job.shared() ? job.anyRank(printsOnly) : printsOnly) {
            const bool rootPrints = job.shared() ? job.fromRoot(printsOnly) : printsOnly;
            if (!printsOnly) {
                std::fprintf(stderr,
                             "vkrt: rank %d: error: another rank was given --help or --list-devices, so "
                             "this one renders nothing; give every rank the same options\n",
                             job.rank());
                return kExitBadInput;
            }
            if (job.rank() == 0 || !rootPrints) {
                printInformation(options);
                // Standard output that takes nothing (a full disk, /dev/full, a closed pipe) is a failure.
                if (std::fflush(stdout) != 0 || std::ferror(stdout))
                    return fail(job, kExitRuntimeFailure, "error: cannot write to standard output");
            }
            return 0;
        }
        handleStopSignals();
        return run(std::move(options), job);
    } catch (const InterruptedBeforeRender& e) {
        return fail(job, stoppedExitCode(),
                    (std::string("interrupted ") + e.what + "; nothing written").c_str());
    } catch (const UsageError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const SceneError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const MemoryError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const NoSuchDeviceError& e) {
        return fail(job, kExitBadInput, (std::string("error: ") + e.what()).c_str());
    } catch (const std::bad_alloc&) {
        return fail(job, kExitRuntimeFailure, "error: out of memory");
    } catch (const std::exception& e) {
        return fail(job, kExitRuntimeFailure, (std::string("error: ") + e.what()).c_str());
    }
}

}  // namespace
}  // namespace vkrt

int main(int argc, char** argv) {
    vkrt::useHugePageHeap();  // first, while the heap is small (huge_page_heap.h)
    // A reader of stderr or of an output through a pipe that has gone (`vkrt ... 2>&1 | head -1`) makes
    // writes fail instead of ending vkrt by SIGPIPE in the middle of a render, or after it, before its exit
    // code.
    std::signal(SIGPIPE, SIG_IGN);
    // A file-size limit (`ulimit -f`) reached while writing an output makes the write fail, said in one line
    // and the temporary file removed, instead of ending vkrt by SIGXFSZ with the temporary file left half
    // written.
    std::signal(SIGXFSZ, SIG_IGN);
    bool shared = false;
    const int exitCode = vkrt::runJob(argc, argv, shared);
    // A process of its own that a signal stopped ends by it, its outputs written and MPI finalised (mpirun
    // -np 1 is a job too); a rank returns its code to the launcher.
    return shared ? exitCode : vkrt::endStopped(exitCode);
}
