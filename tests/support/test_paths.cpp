#include "support/test_paths.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace vkrt::test {

std::filesystem::path sourceDir() {
    return VKRT_SOURCE_DIR;
}

std::filesystem::path scenesReal() {
    return VKRT_SCENES_REAL;
}

bool haveScenesReal() {
    return std::filesystem::is_directory(scenesReal());
}

std::string shaderCacheDir() {
    return (std::filesystem::temp_directory_path() / "vkrt-test-shader-cache").string();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream file(path, std::ios::binary);
    file << text;
    if (!file) throw std::runtime_error("cannot write " + path.string());
}

std::string readText(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

std::vector<std::filesystem::path> gltfFilesUnder(const std::filesystem::path& folder) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        const std::string extension = entry.path().extension().string();
        if (entry.is_regular_file() && (extension == ".gltf" || extension == ".glb"))
            files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace vkrt::test
