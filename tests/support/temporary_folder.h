// A fresh, empty folder under the system temporary directory, named after the running GoogleTest test.
#pragma once

#include <filesystem>

namespace vkrt::test {

std::filesystem::path temporaryFolder();

}  // namespace vkrt::test
