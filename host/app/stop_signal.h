// SIGINT, SIGTERM and SIGHUP: the first ends the render after the dispatch or pixel in flight, and the
// samples done are written as usual; a second ends the process at once (a hang-up again is the same one). A
// first one while the scene loads ends the process if the render has not begun 3 s later (loading does not
// look for it, and may never end).
#pragma once

#include <atomic>

namespace vkrt {

// Installs the handler of the three signals, each only where it is not ignored when vkrt starts (SIGHUP under
// nohup, SIGINT in a background job of a script).
void handleStopSignals();

// Called where a render begins: a signal that came while loading now stops the render, not the process.
void renderBegins();

// Set by the first signal; the renderers read it through their StopCondition.
const std::atomic<bool>& stopRequested();

// The exit code of a render that was stopped: 128 + the signal, as shells report it; SIGTERM's when no signal
// reached this process (under mpirun an interrupt on another rank stops this one too).
int stoppedExitCode();

// Ends the process as the signal that stopped it would have (a shell running vkrt in a loop or a script then
// stops too: one that sees exit 130 takes the signal as handled and goes on), where `exitCode` is
// stoppedExitCode() and a signal came; otherwise returns `exitCode`. For a process of its own, after its
// outputs are written (ranks of an MPI job return their code to the launcher).
int endStopped(int exitCode);

// Interrupted before the render itself began (while loading, or making the reference of --report): nothing
// to keep. `what` says when, after "interrupted ".
struct InterruptedBeforeRender {
    const char* what = "while rendering the reference for --report";
};

}  // namespace vkrt
