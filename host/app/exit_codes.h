// vkrt's exit codes (README.md, "Exit codes").
#pragma once

namespace vkrt {

constexpr int kExitRuntimeFailure = 1;  // a GPU error, a lost device, out of memory
constexpr int kExitBadInput = 2;        // the command line, the scene, a file; a render that does not fit
constexpr int kExitSignalBase = 128;    // ended by signal N: exit 128 + N, as shells report it

}  // namespace vkrt
