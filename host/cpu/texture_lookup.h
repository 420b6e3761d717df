// Base colour texture lookups for the reference renderer: wrap modes, sRGB decoding, bilinear filtering.
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace vkrt {

// Linear RGBA at texture coordinate `uv` (glTF: origin at the top-left of the image).
glm::dvec4 sampleBaseColor(const Texture& texture, glm::dvec2 uv);

}  // namespace vkrt
