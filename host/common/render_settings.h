// What a render is asked to do and the rays it traced, shared by the CPU reference and the GPU tracer.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace vkrt {

// How samples are spread around a pixel's centre (filter importance sampling: every sample has weight 1).
// Box: the pixel's square; tent: radius 1 pixel; Gaussian: standard deviation 0.5 pixel.
enum class PixelFilter : int { Box = 0, Tent = 1, Gaussian = 2 };

struct RenderSettings {
    int width = 512;
    int height = 512;
    int samplesPerPixel = 16;
    int maxDepth = 8;  // reflection and refraction bounces after the camera ray's hit
    uint32_t seed = 0;
    glm::dvec3 ambient{0.05};     // ambient radiance; lights the diffuse albedo (Whitted's ambient term)
    glm::dvec3 background{0.0};   // radiance seen by rays that leave the scene
    double minThroughput = 1e-3;  // branches of the ray tree weighted less than this are cut
    PixelFilter pixelFilter = PixelFilter::Box;
    int lightSamples = 1;  // area-light samples per shading point (at most VKRT_MAX_LIGHT_SAMPLES)
    // Glossy lobes that are both traced and lit by light samples combine the two by the power heuristic;
    // without it, light samples alone light them (traced lobe rays that find a light add nothing).
    bool multipleImportanceSampling = true;
    int threads = 0;  // CPU renderer: 0 means all hardware threads
};

struct RayCounters {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t secondary = 0;  // reflection and refraction rays
    uint64_t nonFiniteSamples = 0;
    uint64_t total() const { return primary + shadow + secondary; }
};

}  // namespace vkrt
