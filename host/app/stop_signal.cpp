#include "app/stop_signal.h"

#include <signal.h>
#include <time.h>
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

// The first signal's sender (a process that called kill(2); 0 for the terminal's Ctrl-C) and when it came.
// timeout(1) sends its signal to the process and then to its process group, so one request can arrive twice
// within microseconds from one sender; such a repeat within kSameRequestSeconds is that request, not a
// second one (it ended a third of `timeout -s INT` runs at once, with nothing written).
volatile std::sig_atomic_t gSender = 0;
timespec gFirstAt{};
constexpr double kSameRequestSeconds = 0.1;

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

extern "C" void onStopSignal(int signal, siginfo_t* info, void*) {
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe
    const int sender = info != nullptr && info->si_code == SI_USER ? static_cast<int>(info->si_pid) : 0;
    if (gSignal != 0) {
        const double since = static_cast<double>(now.tv_sec - gFirstAt.tv_sec) +
                             1e-9 * static_cast<double>(now.tv_nsec - gFirstAt.tv_nsec);
        if (sender != 0 && sender == gSender && signal == gSignal && since < kSameRequestSeconds) return;
        endBy(signal);  // a second signal: at once
        return;
    }
    // The first: ask the render to stop, and give it a while to begin if it has not.
    gSender = sender;
    gFirstAt = now;
    gSignal = signal;
    gStopRequested.store(true);
    if (!gRendering.load()) {
        std::signal(SIGALRM, onLoadingTooLong);
        alarm(kSecondsToBeginRender);
    }
}

}  // namespace

void handleStopSignals() {
    struct sigaction action {};
    action.sa_sigaction = onStopSignal;
    action.sa_flags = SA_SIGINFO | SA_RESTART;  // as std::signal's, with the sender
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
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

int endStopped(int exitCode) {
    if (gSignal != 0 && exitCode == stoppedExitCode()) {
        std::signal(gSignal, SIG_DFL);
        std::raise(gSignal);
    }
    return exitCode;
}

}  // namespace vkrt
