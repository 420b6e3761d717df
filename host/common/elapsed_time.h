// Wall-clock time measured on the steady clock.
#pragma once

#include <chrono>

namespace vkrt {

// Milliseconds from `start` to now.
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vkrt
