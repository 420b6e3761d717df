// A fresh, empty folder under the system temporary directory, named after the running GoogleTest test and
// the checkout (two checkouts running the same test at once must not share it). It is removed when the test
// ends, unless the test failed.
#pragma once

#include <filesystem>

namespace vkrt::test {

std::filesystem::path temporaryFolder();

}  // namespace vkrt::test
