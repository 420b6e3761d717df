#include "scene/environment_map.h"

#include <cmath>
#include <cstdio>

#include "random.h"
#include "scene/sampling_grid.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

// The share of samples drawn in proportion to solid angle alone, whatever the map's light (defensive
// importance sampling; Hesterberg, "Weighted average importance sampling and defensive mixture
// distributions", 1995). Drawn by luminance alone, a sky beside a sun a million times as bright got a
// millionth of the samples, and a point in the sun's shadow an estimate of the sky made of rare, huge samples
// (Whitted has no other way to the sky). A tenth costs a map without such a range at most a tenth more
// variance.
constexpr double kSpreadShare = 0.1;

// A cumulative table on the random numbers' grid (scene/sampling_grid.h), as probabilities.
void toGridCdf(const std::vector<double>& weights, double* cdf) {
    const std::vector<uint64_t> steps = gridCdf(weights, VKRT_RANDOM_STEPS);
    for (size_t i = 0; i < steps.size(); ++i) cdf[i] = static_cast<double>(steps[i]) * VKRT_RANDOM_STEP;
}

}  // namespace

EnvironmentMap makeEnvironmentMap(const std::string& path, int width, int height,
                                  std::vector<glm::vec3> texels, double rotationDegrees, double strength) {
    if (width <= 0 || height <= 0 || texels.size() != static_cast<size_t>(width) * height) {
        throw SceneError(path + ": the environment map is empty or incomplete");
    }
    if (static_cast<uint64_t>(width) > VKRT_RANDOM_STEPS ||
        static_cast<uint64_t>(height) > VKRT_RANDOM_STEPS) {
        throw SceneError(path + ": the environment map is wider or taller than " +
                         std::to_string(VKRT_RANDOM_STEPS) +
                         " texels, more than its sampling tables can hold");
    }
    for (size_t i = 0; i < texels.size(); ++i) {
        const glm::vec3& t = texels[i];
        for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(t[c]) || t[c] < 0.0f) {
                throw SceneError(path + ": texel (" + std::to_string(i % width) + ", " +
                                 std::to_string(i / width) + ") of the environment map is " +
                                 (std::isfinite(t[c]) ? "negative" : "not finite"));
            }
        }
    }
    // Scaled, every texel must still be a float: one beyond made the sampling tables NaN and the image wrong.
    for (size_t i = 0; i < texels.size(); ++i) {
        glm::vec3& t = texels[i];
        t = glm::vec3(glm::dvec3(t) * strength);  // in double: a strength below float's range scales too
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            char factor[32];
            std::snprintf(factor, sizeof factor, "%g", strength);
            throw SceneError(path + ": texel (" + std::to_string(i % width) + ", " +
                             std::to_string(i / width) + ") of the environment map times the strength " +
                             factor + " is beyond single precision's range");
        }
    }
    return {.path = path,
            .width = width,
            .height = height,
            .radiance = std::move(texels),
            .rotationDegrees = rotationDegrees,
            .strength = strength};
}

EnvironmentDistribution EnvironmentDistribution::build(const EnvironmentMap& map) {
    EnvironmentDistribution d;
    const size_t width = static_cast<size_t>(map.width), height = static_cast<size_t>(map.height);
    d.columnCdf.resize(width * height);
    d.rowCdf.resize(height);
    // Each texel's weight: its luminance plus the spread's share, times the solid angle its row covers,
    // sin(theta) at the row's centre. The spread adds the same to every texel: the mean luminance over the
    // sphere times kSpreadShare / (1 - kSpreadShare).
    std::vector<double> sinTheta(height), rowLuminance(height, 0.0);
    double lit = 0.0, solidAngle = 0.0;
    for (size_t y = 0; y < height; ++y) {
        sinTheta[y] = std::sin(M_PI * (static_cast<double>(y) + 0.5) / static_cast<double>(height));
        for (size_t x = 0; x < width; ++x)
            rowLuminance[y] += shading::luminance(glm::dvec3(map.radiance[y * width + x]));
        lit += rowLuminance[y] * sinTheta[y];
        solidAngle += static_cast<double>(width) * sinTheta[y];
    }
    const double spread = kSpreadShare / (1.0 - kSpreadShare) * lit / solidAngle;
    // Each row's conditional table (sin(theta) is common to a row's texels), then the marginal table of the
    // rows' weights.
    std::vector<double> weights(width);
    for (size_t y = 0; y < height; ++y) {
        for (size_t x = 0; x < width; ++x)
            weights[x] = shading::luminance(glm::dvec3(map.radiance[y * width + x])) + spread;
        toGridCdf(weights, &d.columnCdf[y * width]);
    }
    std::vector<double> rowWeights(height);
    for (size_t y = 0; y < height; ++y)
        rowWeights[y] = (rowLuminance[y] + spread * static_cast<double>(width)) * sinTheta[y];
    toGridCdf(rowWeights, d.rowCdf.data());
    return d;
}

shading::EnvironmentMapInfo environmentMapInfo(const EnvironmentMap& map) {
    const double rotation = map.rotationDegrees * M_PI / 180.0;
    shading::EnvironmentMapInfo info;
    info.width = static_cast<uint32_t>(map.width);
    info.height = static_cast<uint32_t>(map.height);
    info.cosRotation = std::cos(rotation);
    info.sinRotation = std::sin(rotation);
    return info;
}

}  // namespace vkrt
