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

// How two renders of the same scene by different renderers agree at the scale of their structure rather than
// their noise: the means of `block` x `block` squares of pixels, and of each channel over the whole image.
struct BlockAgreement {
    int blocks = 0;
    double fractionWithin = 0.0;   // blocks whose every channel mean is within the tolerance
    double worstBlock = 0.0;       // the largest relative difference of a block's channel mean
    glm::dvec3 meanRatio{1.0};     // image / reference, per channel mean over the whole image (0 / 0 is 1)
};

// Compares `image` against `reference` (same size; partial blocks at the right and bottom edges are left out).
// A block's channel is within when |a - b| <= relativeTolerance * b + absoluteFloor.
BlockAgreement compareBlocks(const Image& image, const Image& reference, int block, double relativeTolerance,
                             double absoluteFloor = 1e-3);

}  // namespace vkrt
