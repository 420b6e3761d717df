// Where the tests find their inputs: the source tree, the third-party scenes beside the checkout, the
// shader cache kept in the build's temporary folder; and small file helpers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vkrt::test {

std::filesystem::path sourceDir();
std::filesystem::path scenesReal();  // ../shared/scenes-real beside the checkout
bool haveScenesReal();

// The shader cache the GPU tests and the stability suite share, away from the user's cache.
std::string shaderCacheDir();

void writeText(const std::filesystem::path& path, const std::string& text);
std::string readText(const std::filesystem::path& path);  // the whole file; empty when it cannot be read

// Every .gltf and .glb file under a folder, sorted.
std::vector<std::filesystem::path> gltfFilesUnder(const std::filesystem::path& folder);

}  // namespace vkrt::test
