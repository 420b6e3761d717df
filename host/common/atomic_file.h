// Writing a file so that readers see either nothing or the whole file: write to a temporary name in the
// same folder, then rename it into place (rename is atomic within a file system).
#pragma once

#include <filesystem>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace vkrt {

// Calls write(temporaryPath), then renames the temporary file to `path`. If write throws or the rename
// fails, the temporary file is removed and nothing appears at `path`.
template <typename Write>
void writeFileAtomically(const std::string& path, Write&& write) {
    std::random_device device;
    std::ostringstream name;
    name << path << ".tmp-" << std::hex << device() << device();
    const std::string temporary = name.str();
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
