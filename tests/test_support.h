// Helpers shared by the tests: paths, temporary folders, writing small glTF files, running the command.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "image/image.h"
#include "scene/scene.h"

namespace vkrt::test {

std::filesystem::path sourceDir();
std::filesystem::path scenesReal();  // ../shared/scenes-real beside the checkout
bool haveScenesReal();

// A fresh, empty folder under the system temporary directory, named after the running test.
std::filesystem::path temporaryFolder();

void writeText(const std::filesystem::path& path, const std::string& text);

// Every .gltf and .glb file under a folder, sorted.
std::vector<std::filesystem::path> gltfFilesUnder(const std::filesystem::path& folder);

struct CommandResult {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};

// Runs the vkrt binary with the given arguments (already quoted where needed), validation layer on.
CommandResult runVkrt(const std::string& arguments);

// Writes an image and the absolute difference beside it, for a person to look at when a test fails.
void saveForInspection(const Image& image, const Image& reference, const std::string& name);

}  // namespace vkrt::test
