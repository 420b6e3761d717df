#include "image/image_metrics.h"

#include <algorithm>
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

BlockAgreement compareBlocks(const Image& image, const Image& reference, int block, double relativeTolerance,
                             double absoluteFloor) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("compareBlocks: sizes differ");
    }
    if (block < 1) throw std::invalid_argument("compareBlocks: the block size must be positive");
    BlockAgreement agreement;
    int within = 0;
    for (int by = 0; by + block <= image.height; by += block) {
        for (int bx = 0; bx + block <= image.width; bx += block) {
            glm::dvec3 a(0.0), b(0.0);
            for (int y = by; y < by + block; ++y) {
                for (int x = bx; x < bx + block; ++x) {
                    a += glm::dvec3(image.at(x, y));
                    b += glm::dvec3(reference.at(x, y));
                }
            }
            a /= static_cast<double>(block * block);
            b /= static_cast<double>(block * block);
            bool blockWithin = true;
            for (int c = 0; c < 3; ++c) {
                const double difference = std::abs(a[c] - b[c]);
                agreement.worstBlock = std::max(agreement.worstBlock, difference / (std::abs(b[c]) + absoluteFloor));
                if (!(difference <= relativeTolerance * std::abs(b[c]) + absoluteFloor)) blockWithin = false;
            }
            within += blockWithin ? 1 : 0;
            ++agreement.blocks;
        }
    }
    agreement.fractionWithin = agreement.blocks > 0 ? static_cast<double>(within) / agreement.blocks : 0.0;
    glm::dvec3 sumImage(0.0), sumReference(0.0);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        sumImage += glm::dvec3(image.pixels[i]);
        sumReference += glm::dvec3(reference.pixels[i]);
    }
    // A channel black throughout the reference agrees only with black (ratio 1); any light there is
    // infinitely more (a ratio of 0 read as agreement's opposite, and hid light where the reference had
    // none).
    for (int c = 0; c < 3; ++c) {
        agreement.meanRatio[c] = sumReference[c] > 0.0 ? sumImage[c] / sumReference[c]
                                 : sumImage[c] == 0.0  ? 1.0
                                                       : std::numeric_limits<double>::infinity();
    }
    return agreement;
}

}  // namespace vkrt
