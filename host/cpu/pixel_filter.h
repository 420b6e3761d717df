// Filter importance sampling: where a sample lands relative to its pixel's centre, from two numbers in
// [0, 1), so that averaging the samples gives the image filtered by the box, tent or Gaussian filter.
// shaders/trace.comp's filterOffset() computes the same in single precision.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "common/render_settings.h"

namespace vkrt {

// The inverse CDF of the tent filter of radius 1 on [-1, 1].
inline double tentInverse(double u) {
    return u < 0.5 ? std::sqrt(2.0 * u) - 1.0 : 1.0 - std::sqrt(2.0 - 2.0 * u);
}

inline glm::dvec2 filterOffset(PixelFilter filter, double u, double v) {
    switch (filter) {
        case PixelFilter::Tent:
            return {tentInverse(u), tentInverse(v)};
        case PixelFilter::Gaussian: {
            // Box-Muller with standard deviation 0.5 pixel.
            const double radius = 0.5 * std::sqrt(-2.0 * std::log(1.0 - u));
            return {radius * std::cos(2.0 * M_PI * v), radius * std::sin(2.0 * M_PI * v)};
        }
        case PixelFilter::Box:
        default:
            return {u - 0.5, v - 0.5};
    }
}

}  // namespace vkrt
