// What a file's name says of it.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace vkrt {

// The extension of `path` in lower case, with its dot (".exr"); empty for none. Formats are chosen by it, so
// "A.PFM" and "r.CSV" are what "a.pfm" and "r.csv" are.
inline std::string lowerExtension(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

}  // namespace vkrt
