#include "scene/environment_map.h"

#include <cmath>
#include <cstdio>

#include "scene/scene_error.h"

namespace vkrt {
namespace {

// Turns `weights` into its cumulative table in place, normalised to end at exactly 1; weights that sum to
// zero become uniform (pbrt-v4, PiecewiseConstant1D). Returns the sum.
double toCdf(double* weights, size_t count) {
    double sum = 0.0;
    for (size_t i = 0; i < count; ++i) sum += weights[i];
    double running = 0.0;
    for (size_t i = 0; i < count; ++i) {
        running += sum > 0.0 ? weights[i] : 1.0;
        weights[i] = running / (sum > 0.0 ? sum : static_cast<double>(count));
    }
    weights[count - 1] = 1.0;
    return sum;
}

}  // namespace

EnvironmentMap makeEnvironmentMap(const std::string& path, int width, int height,
                                  std::vector<glm::vec3> texels, double rotationDegrees, double strength) {
    if (width <= 0 || height <= 0 || texels.size() != static_cast<size_t>(width) * height) {
        throw SceneError(path + ": the environment map is empty or incomplete");
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
    for (size_t y = 0; y < height; ++y) {
        // Each texel's weight: its luminance times the solid angle its row covers, sin(theta) at the centre.
        const double sinTheta = std::sin(M_PI * (static_cast<double>(y) + 0.5) / static_cast<double>(height));
        double* row = &d.columnCdf[y * width];
        for (size_t x = 0; x < width; ++x) {
            row[x] = shading::luminance(glm::dvec3(map.radiance[y * width + x])) * sinTheta;
        }
        // The row's conditional table; its sum is the row's weight in the marginal table.
        d.rowCdf[y] = toCdf(row, width);
    }
    toCdf(d.rowCdf.data(), height);
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
