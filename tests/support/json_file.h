// Reading a JSON file a command wrote (--stats, reports).
#pragma once

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace vkrt::test {

inline nlohmann::json readJson(const std::filesystem::path& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
}

}  // namespace vkrt::test
