// What a render will hold in memory, part by part, and the error raised when that does not fit: vkrt
// estimates before it allocates (issue 14), so a render too big for the machine is refused at once with the
// figures, not minutes later by the allocator.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace vkrt {

// A render that does not fit the memory at hand: bad input for this machine (exit code 2), not a failure.
class MemoryError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// "512 B", "3.0 KiB", "1.25 GiB": three significant digits, binary units.
inline std::string formatBytes(uint64_t bytes) {
    static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
    if (bytes < 1024) return std::to_string(bytes) + " B";
    double value = static_cast<double>(bytes);
    int unit = 0;
    while (value >= 1024.0 && unit < 5) {
        value /= 1024.0;
        ++unit;
    }
    char text[32];
    std::snprintf(text, sizeof(text),
                  value < 10.0    ? "%.2f %s"
                  : value < 100.0 ? "%.1f %s"
                                  : "%.0f %s",
                  value, kUnits[unit]);
    return text;
}

// A byte count figured in double from counts a file claims, saturated below 2^64 rather than wrapped.
inline uint64_t saturatedBytes(double bytes) {
    return static_cast<uint64_t>(std::min(bytes, 1.8e19));
}

class MemoryNeed {
  public:
    struct Part {
        std::string what;
        uint64_t bytes = 0;
    };

    void add(std::string what, uint64_t bytes) {
        if (bytes > 0) parts_.push_back({std::move(what), bytes});
    }
    uint64_t total() const {
        uint64_t sum = 0;
        for (const Part& p : parts_) sum += p.bytes;
        return sum;
    }
    const std::vector<Part>& parts() const { return parts_; }
    // The largest single part (one allocation, where each part is one).
    Part largest() const {
        Part best;
        for (const Part& p : parts_)
            if (p.bytes > best.bytes) best = p;
        return best;
    }
    // "2.10 GiB (image 1.00 GiB, BVH 820 MiB, ...)", largest parts first, at most four named.
    std::string describe() const {
        std::vector<Part> sorted = parts_;
        std::stable_sort(sorted.begin(), sorted.end(),
                         [](const Part& a, const Part& b) { return a.bytes > b.bytes; });
        std::string text = formatBytes(total());
        if (sorted.empty()) return text;
        text += " (";
        uint64_t rest = 0;
        for (size_t i = 0; i < sorted.size(); ++i) {
            if (i < 4) {
                text += (i ? ", " : "") + sorted[i].what + " " + formatBytes(sorted[i].bytes);
            } else {
                rest += sorted[i].bytes;
            }
        }
        if (rest > 0) text += ", other " + formatBytes(rest);
        return text + ")";
    }

  private:
    std::vector<Part> parts_;
};

}  // namespace vkrt
