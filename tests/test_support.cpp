#include "test_support.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "image/image_io.h"

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

std::filesystem::path temporaryFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "vkrt-test";
    std::replace(name.begin(), name.end(), '/', '_');
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("vkrt-test-" + name);
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream file(path, std::ios::binary);
    file << text;
    if (!file) throw std::runtime_error("cannot write " + path.string());
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

CommandResult runVkrt(const std::string& arguments) {
    // Every GPU run in the suite is checked by the Khronos validation layer (vkrt fails on any message).
    const std::string command = std::string("VKRT_VALIDATE=1 '") + VKRT_BINARY + "' " + arguments + " 2>&1";
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

void saveForInspection(const Image& image, const Image& reference, const std::string& name) {
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "vkrt-test-failures";
    std::filesystem::create_directories(folder);
    Image difference(image.width, image.height);
    for (size_t i = 0; i < image.pixels.size() && i < reference.pixels.size(); ++i) {
        difference.pixels[i] = glm::abs(image.pixels[i] - reference.pixels[i]);
    }
    writeImage(image, (folder / (name + "-image.pfm")).string());
    writeImage(reference, (folder / (name + "-reference.pfm")).string());
    writeImage(difference, (folder / (name + "-difference.pfm")).string());
    std::fprintf(stderr, "images written to %s/%s-*.pfm\n", folder.c_str(), name.c_str());
}

}  // namespace vkrt::test
