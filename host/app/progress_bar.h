// Progress on stderr: a bar with elapsed time and ETA, redrawn in place, where stderr is a terminal;
// elsewhere (a log, a pipe, mpirun's forwarding) a line now and then, so that long renders say how far they
// are.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace vkrt {

class ProgressBar {
  public:
    // `out` and `lineEvery` (the interval of lines where `out` is no terminal) are for tests.
    ProgressBar(std::string label, bool enabled, std::FILE* out = stderr,
                std::chrono::milliseconds lineEvery = std::chrono::seconds(10));
    void update(uint64_t done, uint64_t total);
    void finish();

  private:
    enum class Mode { Off, Bar, Lines };
    std::string label_;
    Mode mode_;
    std::FILE* out_;
    std::chrono::milliseconds lineEvery_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastDraw_;
    bool drawn_ = false;
};

}  // namespace vkrt
