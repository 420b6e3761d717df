// A fresh, empty folder under the system temporary directory, named after the running GoogleTest test and
// the checkout (two checkouts running the same test at once must not share it).
#pragma once

#include <filesystem>

namespace vkrt::test {

std::filesystem::path temporaryFolder();

}  // namespace vkrt::test
