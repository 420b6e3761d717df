// Writing a file so that readers see either nothing or the whole file: write to a temporary name in the
// same folder, then rename it into place (rename is atomic within a file system).
#pragma once

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace vkrt {

// "`path`: cannot write", with the system's reason where the failed call left one (a full disk: "No space
// left on device"). Called right after the write or flush that failed.
inline std::string cannotWrite(const std::string& path) {
    const int error = errno;
    return path + ": cannot write" +
           (error != 0 ? std::string(" (") + std::strerror(error) + ")" : std::string());
}

// Where writing `path` goes: through a symbolic link to the file it names (so the link stays a link), and
// `direct` when that is not a regular file or a new one (a device such as /dev/stdout, or a pipe), which is
// written as it is, since it cannot be replaced by a rename.
struct OutputTarget {
    std::filesystem::path path;
    bool direct = false;
};

inline OutputTarget outputTarget(const std::string& path) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);  // through links
    if (!error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
        !std::filesystem::is_directory(status)) {
        return {path, true};
    }
    // Each link in turn (the file it names need not exist yet), at most as many as the system follows.
    std::filesystem::path file(path);
    for (int links = 0;
         links < 40 && std::filesystem::is_symlink(std::filesystem::symlink_status(file, error)); ++links) {
        const std::filesystem::path target = std::filesystem::read_symlink(file, error);
        if (error) break;
        file = target.is_absolute() ? target : file.parent_path() / target;
    }
    return {file, false};
}

// The temporary file being written, for a signal handler that ends the process to remove (unlink() is
// async-signal-safe): empty when none, or a path longer than the buffer.
inline char gTemporaryFileBeingWritten[4096] = {};

// Calls write(temporaryPath), then renames the temporary file to `path`. If write throws or the rename
// fails, the temporary file is removed and nothing appears at `path`.
template <typename Write>
void writeFileAtomically(const std::string& asked, Write&& write) {
    const OutputTarget output = outputTarget(asked);
    if (output.direct) {
        write(asked);
        return;
    }
    const std::string path = output.path.string();
    std::random_device device;
    std::ostringstream suffix;
    suffix << ".tmp-" << std::hex << std::setfill('0') << std::setw(8) << device() << std::setw(8)
           << device();
    // The file's name and the suffix, the name cut short where both would pass the 255 bytes a file name may
    // have (a valid name of 235 bytes or more had the write fail after the render).
    const std::filesystem::path target(path);
    std::string name = target.filename().string();
    constexpr size_t kLongestName = 255;
    if (name.size() > kLongestName - suffix.str().size()) {
        name.resize(kLongestName - suffix.str().size());
        while (!name.empty() && (static_cast<unsigned char>(name.back()) & 0xc0u) == 0x80u)
            name.pop_back();  // not inside a UTF-8 character
        if (!name.empty() && (static_cast<unsigned char>(name.back()) & 0x80u) != 0)
            name.pop_back();  // its lead
    }
    const std::string temporary = (target.parent_path() / (name + suffix.str())).string();
    struct Published {  // the temporary file's name, visible to a signal handler while it exists
        explicit Published(const std::string& file) {
            if (file.size() < sizeof(gTemporaryFileBeingWritten))
                std::copy(file.c_str(), file.c_str() + file.size() + 1, gTemporaryFileBeingWritten);
        }
        ~Published() { gTemporaryFileBeingWritten[0] = '\0'; }
    } published(temporary);
    try {
        write(temporary);
        std::error_code error;
        std::filesystem::rename(temporary, path, error);
        if (error)
            throw std::runtime_error(path + ": cannot move the finished file into place: " + error.message());
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace vkrt
