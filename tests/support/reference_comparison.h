// An image against its reference (GPU against the double-precision CPU reference with the same seed, or a
// variant against the unchanged scene), and the images written out for a person to look at. Shared by the
// GPU tests and the numerical-stability suite, so both hold the same tolerances.
#pragma once

#include <filesystem>
#include <string>

#include "image/image.h"
#include "image/image_metrics.h"

namespace vkrt::test {

// A pixel is off when some channel differs by more than 1% of the reference plus 2e-3 (a floor for dark
// pixels).
inline constexpr double kPixelRelativeTolerance = 0.01;
inline constexpr double kPixelAbsoluteFloor = 2e-3;
// An image matches the reference when at most 0.5% of its pixels are off and its mean relative error is at
// most 0.2%.
inline constexpr double kMaxFractionOff = 0.005;
inline constexpr double kMaxMeanRelativeError = 0.002;

// compareImages with the per-pixel tolerance above.
ImageDifference compareWithReference(const Image& image, const Image& reference);

// Whether a difference from compareWithReference is within the image-level thresholds above.
bool withinReferenceThresholds(const ImageDifference& difference);

// Writes FOLDER/NAME-image.pfm, NAME-reference.pfm and NAME-difference.pfm (the absolute difference).
void writeComparisonImages(const std::filesystem::path& folder, const std::string& name, const Image& image,
                           const Image& reference);

// writeComparisonImages into $TMPDIR/vkrt-test-failures, saying where on stderr: for a failing test.
void saveForInspection(const Image& image, const Image& reference, const std::string& name);

}  // namespace vkrt::test
