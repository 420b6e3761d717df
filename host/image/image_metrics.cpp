#include "image/image_metrics.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vkrt {

ImageDifference compareImages(const Image& image, const Image& reference, double relativeTolerance,
                              double absoluteFloor) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("compareImages: sizes differ");
    }
    ImageDifference difference;
    double squared = 0.0, relative = 0.0, relativeAbsolute = 0.0;
    size_t off = 0;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        bool pixelOff = false;
        for (int c = 0; c < 3; ++c) {
            const double a = image.pixels[i][c], b = reference.pixels[i][c];
            const double d = a - b;
            squared += d * d;
            relative += d * d / (b * b + 0.01);
            relativeAbsolute += std::abs(d) / (std::abs(b) + absoluteFloor);
            if (!(std::abs(d) <= relativeTolerance * std::abs(b) + absoluteFloor)) pixelOff = true;
        }
        off += pixelOff ? 1 : 0;
    }
    const double n = static_cast<double>(image.pixels.size()) * 3.0;
    if (n == 0.0) return difference;
    difference.rmse = std::sqrt(squared / n);
    difference.relMse = relative / n;
    difference.meanRelativeError = relativeAbsolute / n;
    difference.psnr = difference.rmse > 0.0 ? 20.0 * std::log10(1.0 / difference.rmse)
                                            : std::numeric_limits<double>::infinity();
    difference.fractionOff = static_cast<double>(off) / static_cast<double>(image.pixels.size());
    return difference;
}

}  // namespace vkrt
