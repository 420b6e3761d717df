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

}  // namespace vkrt
