#include "support/reference_comparison.h"

#include <cstdio>

#include "image/image_io.h"

namespace vkrt::test {

ImageDifference compareWithReference(const Image& image, const Image& reference) {
    return compareImages(image, reference, kPixelRelativeTolerance, kPixelAbsoluteFloor);
}

bool withinReferenceThresholds(const ImageDifference& difference) {
    return difference.fractionOff <= kMaxFractionOff && difference.meanRelativeError <= kMaxMeanRelativeError;
}

void writeComparisonImages(const std::filesystem::path& folder, const std::string& name, const Image& image,
                           const Image& reference) {
    std::filesystem::create_directories(folder);
    Image difference(image.width, image.height);
    for (size_t i = 0; i < image.pixels.size() && i < reference.pixels.size(); ++i) {
        difference.pixels[i] = glm::abs(image.pixels[i] - reference.pixels[i]);
    }
    writeImage(image, (folder / (name + "-image.pfm")).string());
    writeImage(reference, (folder / (name + "-reference.pfm")).string());
    writeImage(difference, (folder / (name + "-difference.pfm")).string());
}

void saveForInspection(const Image& image, const Image& reference, const std::string& name) {
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "vkrt-test-failures";
    writeComparisonImages(folder, name, image, reference);
    std::fprintf(stderr, "images written to %s/%s-*.pfm\n", folder.c_str(), name.c_str());
}

}  // namespace vkrt::test
