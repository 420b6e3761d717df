// A progress bar with elapsed time and ETA on stderr, drawn only when stderr is a terminal.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace vkrt {

class ProgressBar {
  public:
    ProgressBar(std::string label, bool enabled);
    void update(uint64_t done, uint64_t total);
    void finish();

  private:
    std::string label_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastDraw_;
    bool drawn_ = false;
};

}  // namespace vkrt
