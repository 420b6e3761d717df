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

// How long a stop asked for before the render began waits for it to begin (then stops it after its first
// dispatch or pixel, keeping those samples): loading a scene does not look for the request, and may never end
// (a named pipe, a file that hangs a decoder).
constexpr unsigned kSecondsToBeginRender = 3;

// Ends the process as `signal` would have, removing the file being written.
void endBy(int signal) {
    if (gTemporaryFileBeingWritten[0] != '\0') unlink(gTemporaryFileBeingWritten);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

extern "C" void onLoadingTooLong(int) {
    endBy(gSignal != 0 ? gSignal : SIGTERM);
}

extern "C" void onStopSignal(int signal) {
    if (gSignal != 0) {  // a second signal: at once
        endBy(signal);
        return;
    }
    // The first: ask the render to stop, and give it a while to begin if it has not.
    gSignal = signal;
    gStopRequested.store(true);
    if (!gRendering.load()) {
        std::signal(SIGALRM, onLoadingTooLong);
        alarm(kSecondsToBeginRender);
    }
}

}  // namespace

void handleStopSignals() {
    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
}

void renderBegins() {
    gRendering.store(true);
    alarm(0);  // a stop asked for while loading now stops the render
}

const std::atomic<bool>& stopRequested() {
    return gStopRequested;
}

int stoppedExitCode() {
    return kExitSignalBase + (gSignal != 0 ? gSignal : SIGTERM);
}

}  // namespace vkrt
