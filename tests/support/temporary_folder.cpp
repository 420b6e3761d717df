#include "support/temporary_folder.h"

#include <algorithm>
#include <functional>
#include <sstream>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

#include "support/test_paths.h"

namespace vkrt::test {
namespace {

// Removes the running test's folder when the test ends unless it failed: a failed test's files stay for a
// look at what it wrote, until the test runs again.
class RemoveUnlessFailed : public ::testing::EmptyTestEventListener {
  public:
    void OnTestEnd(const ::testing::TestInfo& info) override {
        if (folder.empty()) return;
        std::error_code ignored;
        if (!info.result()->Failed()) std::filesystem::remove_all(folder, ignored);
        folder.clear();
    }
    std::filesystem::path folder;
};

RemoveUnlessFailed& remover() {
    // GoogleTest owns and deletes its listeners.
    static RemoveUnlessFailed* const listener = [] {
        auto* created = new RemoveUnlessFailed;
        ::testing::UnitTest::GetInstance()->listeners().Append(created);
        return created;
    }();
    return *listener;
}

}  // namespace

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
    // Made outside a test (a suite's set-up), it outlives the test that ends next.
    if (info) remover().folder = folder;
    return folder;
}

}  // namespace vkrt::test
