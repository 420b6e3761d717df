#include "app/stop_signal.h"

#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>

#include "app/exit_codes.h"
#include "common/atomic_file.h"

namespace vkrt {
namespace {

std::atomic<bool> gStopRequested{false};
std::atomic<bool> gRendering{false};
std::atomic<int> gSignal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free &&
                  std::atomic<int64_t>::is_always_lock_free,
              "set from a signal handler");

// The first signal's sender (a process that called kill(2); 0 for the terminal's Ctrl-C) and when it came, in
// nanoseconds, published before gSignal. timeout(1) sends its signal to the process and then to its process
// group, so one request can arrive twice within microseconds from one sender (the second perhaps handled on
// another thread while the first still is); such a repeat within kSameRequestNs is that request, not a second
// one (it ended a third of `timeout -s INT` runs at once, with nothing written).
std::atomic<int> gSender{0};
std::atomic<int64_t> gFirstAtNs{0};
constexpr int64_t kSameRequestNs = 100000000;

// How long a stop asked for before the render began waits for it to begin (where the render then begins,
// it ends with nothing written: no pixel has a sample): loading a scene does not look for the request, and
// may never end (a named pipe, a file that hangs a decoder).
constexpr unsigned kSecondsToBeginRender = 3;

// Ends the process as `signal` would have, removing the files being written.
void endBy(int signal) {
    for (const char* file : gTemporaryFilesBeingWritten) {
        if (file[0] != '\0') unlink(file);
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

extern "C" void onLoadingTooLong(int) {
    const int signal = gSignal.load();
    endBy(signal != 0 ? signal : SIGTERM);
}

extern "C" void onStopSignal(int signal, siginfo_t* info, void*) {
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe
    const int64_t nowNs = static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
    const int sender = info != nullptr && info->si_code == SI_USER ? static_cast<int>(info->si_pid) : 0;
    // A hang-up comes more than once as a terminal goes (from the shell, which passes it on to its jobs, and
    // from the system when the shell has exited), and no person sends a second one to end vkrt at once.
    auto sameRequest = [&](int first) {
        if (signal == SIGHUP && first == SIGHUP) return true;
        return signal == first && sender != 0 && sender == gSender.load() &&
               nowNs - gFirstAtNs.load() < kSameRequestNs;
    };
    int first = gSignal.load();
    if (first != 0) {
        if (sameRequest(first)) return;
        endBy(signal);  // a second signal: at once
        return;
    }
    // The first (or a repeat handled beside it on another thread, which then finds it below).
    gSender.store(sender);
    gFirstAtNs.store(nowNs);
    if (!gSignal.compare_exchange_strong(first, signal)) {
        if (sameRequest(first)) return;
        endBy(signal);
        return;
    }
    // Ask the render to stop, and give it a while to begin if it has not.
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
    sigemptyset(&action.sa_mask);               // none interrupts another's handler on its thread
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, signal);
    // A signal ignored when vkrt starts stays ignored, as the one who started it asked: under nohup a
    // hang-up, and in a background job of a script (a shell without job control) Ctrl-C, which the terminal
    // sends to the script's every process, and which stopped the job's render where the script went on with
    // it. A hang-up heard (the terminal closed, an ssh session lost) ended vkrt at once, a temporary file
    // left half written, where SIGTERM keeps the samples done.
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction before {};
        if (sigaction(signal, nullptr, &before) == 0 && before.sa_handler != SIG_IGN)
            sigaction(signal, &action, nullptr);
    }
}

void renderBegins() {
    gRendering.store(true);
    alarm(0);  // a stop asked for while loading now stops the render
}

const std::atomic<bool>& stopRequested() {
    return gStopRequested;
}

int stoppedExitCode() {
    const int signal = gSignal.load();
    return kExitSignalBase + (signal != 0 ? signal : SIGTERM);
}

int endStopped(int exitCode) {
    const int signal = gSignal.load();
    if (signal != 0 && exitCode == stoppedExitCode()) {
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
    return exitCode;
}

}  // namespace vkrt
