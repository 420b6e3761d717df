#include "support/temporary_folder.h"

#include <algorithm>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_paths.h"

namespace vkrt::test {

std::filesystem::path temporaryFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "vkrt-test";
    std::replace(name.begin(), name.end(), '/', '_');
    // Checkouts on one machine share the temporary directory: the folder names this one too.
    std::ostringstream checkout;
    checkout << std::hex << (std::hash<std::string>{}(sourceDir().string()) & 0xffffffu);
    name.append("-").append(checkout.str());
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("vkrt-test-" + name);
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

}  // namespace vkrt::test
