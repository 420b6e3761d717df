#include "app/path_checks.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "common/atomic_file.h"

namespace vkrt {
namespace {

void checkReadable(const char* option, const std::string& path) {
    if (path.empty()) return;
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (status.type() == std::filesystem::file_type::not_found)
        throw UsageError(std::string(option) + ": " + path + ": cannot open: no such file");
    if (status.type() == std::filesystem::file_type::directory)
        throw UsageError(std::string(option) + ": " + path + ": is a directory");
    // A device may have no end to read to (/dev/zero filled the memory). A named pipe (a shell's `<(...)`) is
    // read once by its loader: opening it here would wait for a writer and then drop what it wrote.
    if (status.type() == std::filesystem::file_type::character ||
        status.type() == std::filesystem::file_type::block ||
        status.type() == std::filesystem::file_type::socket)
        throw UsageError(std::string(option) + ": " + path + ": is a device, not a file");
    const bool readable = status.type() == std::filesystem::file_type::fifo
                              ? access(path.c_str(), R_OK) == 0
                              : static_cast<bool>(std::ifstream(path, std::ios::binary));
    if (!readable) throw UsageError(std::string(option) + ": " + path + ": cannot read");
}

// The folder that will hold `path` exists and can take a new file (outputs are written to a temporary file
// there first, then renamed).
void checkWritable(const char* option, const std::string& asked) {
    if (asked.empty()) return;
    const OutputTarget output = outputTarget(asked);
    if (output.direct) {  // a device or a pipe, written as it is
        if (access(asked.c_str(), W_OK) != 0)
            throw UsageError(std::string(option) + ": " + asked + ": is not writable");
        return;
    }
    const std::string path = output.path.string();
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
        throw UsageError(std::string(option) + ": " + path + ": is a directory");
    std::filesystem::path folder = std::filesystem::path(path).parent_path();
    if (folder.empty()) folder = ".";
    if (!std::filesystem::is_directory(folder, error))
        throw UsageError(std::string(option) + ": " + path + ": folder " + folder.string() + " does not exist");
    if (access(folder.c_str(), W_OK | X_OK) != 0)
        throw UsageError(std::string(option) + ": " + path + ": folder " + folder.string() +
                         " is not writable");
    // A name the folder's file system cannot hold failed only at the rename, after the render.
    const long longestName = pathconf(folder.c_str(), _PC_NAME_MAX);
    const std::string name = std::filesystem::path(path).filename().string();
    if (longestName > 0 && name.size() > static_cast<size_t>(longestName)) {
        throw UsageError(std::string(option) + ": " + path + ": the file name has " +
                         std::to_string(name.size()) + " bytes; the folder's file system takes at most " +
                         std::to_string(longestName));
    }
    const long longestPath = pathconf(folder.c_str(), _PC_PATH_MAX);
    if (longestPath > 0 && path.size() >= static_cast<size_t>(longestPath)) {
        throw UsageError(std::string(option) + ": the path has " + std::to_string(path.size()) +
                         " bytes; the system takes fewer than " + std::to_string(longestPath));
    }
    // After the lengths: a name too long fails its lookup too, and is better said as such.
    if (const std::string why = whyNotReplaceable(path); !why.empty())
        throw UsageError(std::string(option) + ": " + path + ": " + why);
}

}  // namespace

void checkPaths(const Options& options) {
    checkReadable("--scene", options.scenePath);
    if (!options.referencePath.empty()) checkReadable("--reference", options.referencePath);
    checkWritable("--out", options.outputPath);
    checkWritable("--stats", options.statsPath);
    checkWritable("--report", options.reportPath);
}

}  // namespace vkrt
