#include "scene/sampling_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vkrt {

std::vector<uint64_t> gridCdf(const std::vector<double>& weights, uint64_t steps) {
    if (weights.size() > steps) throw std::length_error("more table entries than probability steps");
    double sum = 0.0;
    uint64_t positive = 0;
    for (double w : weights) {
        if (w > 0.0) {
            sum += w;
            ++positive;
        }
    }
    const bool uniform = !(sum > 0.0);
    if (uniform) positive = weights.size();
    // Each entry's share in steps: uniformly steps / n, else one plus the steps beyond one for each entry in
    // proportion to its weight. The running sum of shares is rounded to the nearest step, kept at least one
    // step past the entry before (rounding in double could take a share of one below it) and short of the end
    // by a step for each positive entry still to come; the last positive entry ends the table.
    const double scale = uniform ? 0.0 : static_cast<double>(steps - positive) / sum;
    std::vector<uint64_t> cdf(weights.size());
    double running = 0.0;
    uint64_t previous = 0, toCome = positive;
    for (size_t i = 0; i < weights.size(); ++i) {
        if (uniform || weights[i] > 0.0) {
            running += uniform ? static_cast<double>(steps) / static_cast<double>(weights.size())
                               : 1.0 + weights[i] * scale;
            --toCome;
            const uint64_t rounded = static_cast<uint64_t>(std::max(0.0, std::round(running)));
            previous = toCome == 0 ? steps : std::clamp(rounded, previous + 1, steps - toCome);
        }
        cdf[i] = previous;
    }
    return cdf;
}

}  // namespace vkrt
