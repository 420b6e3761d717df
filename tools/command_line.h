// Every tool parses its command line with CLI11 (Debian's libcli11-dev) through this: --help prints the
// usage and exits 0; a bad argument (unknown flag, value out of range, not a number, missing file) prints
// one line, "TOOL: error: WHAT (see --help)", on stderr and exits 2.
#pragma once

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace vkrt {

// The exit code when the tool should stop now (0 after --help, 2 after a bad argument), or nothing.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(error);
        std::string message = error.what();
        std::replace(message.begin(), message.end(), '\n', ' ');
        std::fprintf(stderr, "%s: error: %s (see --help)\n", app.get_name().c_str(), message.c_str());
        return 2;
    }
    return std::nullopt;
}

}  // namespace vkrt
