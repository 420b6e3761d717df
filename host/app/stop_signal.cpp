#include "app/stop_signal.h"

#include <unistd.h>

#include <csignal>

#include "app/exit_codes.h"
#include "common/atomic_file.h"

namespace vkrt {
namespace {

std::atomic<bool> gStopRequested{false};
std::atomic<bool> gRendering{false};
volatile std::sig_atomic_t gSignal = 0;
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void onStopSignal(int signal) {
    // A second signal, or one before the render began (nothing to keep; loading a scene does not look for
    // it): remove the file being written, then end as the signal would have.
    if (gSignal != 0 || !gRendering.load()) {
        if (gTemporaryFileBeingWritten[0] != '\0') unlink(gTemporaryFileBeingWritten);
        std::signal(signal, SIG_DFL);
        std::raise(signal);
        return;
    }
    // The first: ask the render to stop.
    gSignal = signal;
    gStopRequested.store(true);
}

}  // namespace

void handleStopSignals() {
    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
}

void renderBegins() {
    gRendering.store(true);
}

const std::atomic<bool>& stopRequested() {
    return gStopRequested;
}

int stoppedExitCode() {
    return kExitSignalBase + (gSignal != 0 ? gSignal : SIGTERM);
}

}  // namespace vkrt
