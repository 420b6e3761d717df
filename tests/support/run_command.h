// Running a program of the build (the vkrt command, the tools) and collecting its exit code and output.
#pragma once

#include <string>

namespace vkrt::test {

struct CommandResult {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};

// Runs a shell command line and returns its exit code and everything it printed.
CommandResult runCommand(const std::string& commandLine);

// Runs the vkrt binary with the given arguments (already quoted where needed), validation layer on.
CommandResult runVkrt(const std::string& arguments);

}  // namespace vkrt::test
