// What a render is asked to do and the rays it traced, shared by the CPU reference and the GPU tracer.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace vkrt {

// How samples are spread around a pixel's centre (filter importance sampling: every sample has weight 1).
// Box: the pixel's square; tent: radius 1 pixel; Gaussian: standard deviation 0.5 pixel.
enum class PixelFilter : int { Box = 0, Tent = 1, Gaussian = 2 };

// How light is gathered: unidirectional path tracing (Kajiya 1986: every lobe continued by one sampled ray,
// next-event estimation with multiple importance sampling, Russian roulette), or distributed Whitted ray
// tracing (mirror, glossy and refracted rays traced, diffuse light from the lights and an ambient term alone).
enum class Integrator : int { Whitted = 0, Path = 1 };

inline const char* integratorName(Integrator integrator) {
    return integrator == Integrator::Path ? "path" : "whitted";
}

// The most bounces a path may take (Whitted's ray tree is bounded by VKRT_MAX_RAY_DEPTH on the GPU).
inline constexpr int kMaxPathDepth = 1024;

// The largest image side, in pixels (--width, --height, and a height from the camera's aspect ratio).
inline constexpr int kMaxImageSide = 16384;

// The largest seed --seed accepts; a reference rendered for --report takes the next, wrapping to 0.
inline constexpr uint32_t kMaxSeed = 2147483647u;

struct RenderSettings {
    int width = 512;
    int height = 512;
    int samplesPerPixel = 16;
    Integrator integrator = Integrator::Whitted;
    int maxDepth = 8;  // bounces after the camera ray's hit (Whitted: reflection and refraction)
    uint32_t seed = 0;
    glm::dvec3 ambient{0.05};     // ambient radiance; lights the diffuse albedo (Whitted's alone; paths ignore it)
    glm::dvec3 background{0.0};   // radiance seen by rays that leave the scene
    double minThroughput = 1e-3;  // Whitted: branches of the ray tree weighted less than this are cut
    PixelFilter pixelFilter = PixelFilter::Box;
    int lightSamples = 1;  // area-light samples per shading point (at most VKRT_MAX_LIGHT_SAMPLES)
    // Glossy lobes that are both traced and lit by light samples combine the two by the power heuristic;
    // without it, light samples alone light them (traced lobe rays that find a light add nothing).
    bool multipleImportanceSampling = true;
    // Rough GGX lobes make up for the energy that single scattering between microfacets loses (Turquin 2019,
    // shaders/energy_compensation.h); without it a white metal of roughness 1 returns about 40% of the light.
    bool energyCompensation = true;
    int threads = 0;  // CPU renderer: 0 means all hardware threads
};

struct RayCounters {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t secondary = 0;  // reflection and refraction rays; a path's bounces
    uint64_t nonFiniteSamples = 0;
    uint64_t total() const { return primary + shadow + secondary; }
    RayCounters& operator+=(const RayCounters& other) {
        primary += other.primary;
        shadow += other.shadow;
        secondary += other.secondary;
        nonFiniteSamples += other.nonFiniteSamples;
        return *this;
    }
};

}  // namespace vkrt
