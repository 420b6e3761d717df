#include "support/run_command.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <stdexcept>

namespace vkrt::test {

CommandResult runCommand(const std::string& commandLine) {
    const std::string command = commandLine + " 2>&1";
    CommandResult result;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) throw std::runtime_error("cannot run " + command);
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

CommandResult runVkrt(const std::string& arguments) {
    // Every GPU run in the suite is checked by the Khronos validation layer (vkrt fails on any message).
    return runCommand(std::string("VKRT_VALIDATE=1 '") + VKRT_BINARY + "' " + arguments);
}

}  // namespace vkrt::test
