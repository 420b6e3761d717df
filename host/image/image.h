// A linear-light RGB image in single precision, rows top to bottom.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace vkrt {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> pixels;

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * h, glm::vec3(0.0f)) {}
    glm::vec3& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
    const glm::vec3& at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

// Per-pixel averages of (rgb sum, sample count) accumulators; black where no sample counted.
inline Image averageOf(const std::vector<glm::dvec4>& sums, int width, int height) {
    Image image(width, height);
    for (size_t i = 0; i < sums.size() && i < image.pixels.size(); ++i) {
        image.pixels[i] = sums[i].w > 0.0 ? glm::vec3(glm::dvec3(sums[i]) / sums[i].w) : glm::vec3(0.0f);
    }
    return image;
}

}  // namespace vkrt
