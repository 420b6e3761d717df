// The environment light's map and the tables by which both renderers sample it (shaders/environment.h says
// how directions map onto the image and how the tables are read; docs/environment.md what the options do).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "environment.h"

namespace vkrt {

// An equirectangular radiance map, rows top (the zenith, +Y) to bottom, strength already applied.
struct EnvironmentMap {
    std::string path;  // where it was read from (for the stats)
    int width = 0;     // 0: no environment
    int height = 0;
    std::vector<glm::vec3> radiance;
    double rotationDegrees = 0.0;  // about +Y, right-handed
    double strength = 1.0;
    bool neutral = false;  // the render policy's default for scenes without lights (app/render_policy.h)

    bool present() const { return width > 0; }
};

// The map from decoded texels (linear RGB, rows top to bottom), scaled by `strength`. Throws SceneError
// naming `path` when the image is empty or a texel is negative or not finite.
EnvironmentMap makeEnvironmentMap(const std::string& path, int width, int height,
                                  std::vector<glm::vec3> texels, double rotationDegrees, double strength);

// The piecewise-constant 2D distribution over the map's texels (pbrt-v4, PiecewiseConstant2D), proportional
// to luminance plus a tenth's spread over the sphere, times sin(theta) at each row's centre
// (shaders/environment.h, "Sampling"): cumulative tables on the random numbers' grid (scene/sampling_grid.h)
// that end at exactly 1, identical on both devices. A black map is sampled uniformly.
struct EnvironmentDistribution {
    std::vector<double> rowCdf;     // height entries: the probability of rows 0..y
    std::vector<double> columnCdf;  // width x height: within row y, the probability of texels 0..x

    static EnvironmentDistribution build(const EnvironmentMap& map);
};

// The map's size and rotation as the shared code reads them.
shading::EnvironmentMapInfo environmentMapInfo(const EnvironmentMap& map);

// A map with its tables, read on the CPU through the members the shared code calls (VKRT_DEVICE in
// shaders/environment.h); the CPU reference's device forwards to them. Holds a reference to the map.
class EnvironmentTables {
  public:
    EnvironmentTables() = default;  // no environment
    explicit EnvironmentTables(const EnvironmentMap& map)
        : map_(&map), distribution_(EnvironmentDistribution::build(map)), info_(environmentMapInfo(map)) {}

    bool hasEnvironment() const { return map_ != nullptr; }
    glm::uvec2 environmentSize() const { return {info_.width, info_.height}; }
    glm::dvec2 environmentRotation() const { return {info_.cosRotation, info_.sinRotation}; }
    glm::dvec3 environmentTexel(uint32_t i) const { return glm::dvec3(map_->radiance[i]); }
    double environmentRowCdf(uint32_t y) const { return distribution_.rowCdf[y]; }
    double environmentColumnCdf(uint32_t i) const { return distribution_.columnCdf[i]; }

  private:
    const EnvironmentMap* map_ = nullptr;
    EnvironmentDistribution distribution_;
    shading::EnvironmentMapInfo info_{};
};

}  // namespace vkrt
