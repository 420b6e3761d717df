// Image error metrics for tests and convergence reports.
#pragma once

#include "image/image.h"

namespace vkrt {

struct ImageDifference {
    double rmse = 0.0;    // root mean squared error over all channels
    double relMse = 0.0;  // mean of (a - b)^2 / (b^2 + 0.01), the relative MSE of the rendering literature
    double psnr = 0.0;    // peak signal-to-noise ratio in dB, with peak 1
    double fractionOff = 0.0;        // pixels whose largest channel differs by more than `tolerance` relative
    double meanRelativeError = 0.0;  // mean over channels of |a - b| / (|b| + absoluteFloor)
};

// Compares `image` against `reference` (same size). A pixel is "off" when some channel differs by more
// than relativeTolerance * |reference| + absoluteFloor.
ImageDifference compareImages(const Image& image, const Image& reference, double relativeTolerance = 0.01,
                              double absoluteFloor = 1e-3);

}  // namespace vkrt
