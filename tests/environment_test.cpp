// The environment map's shared functions in C++ (shaders/environment.h with host/scene/environment_map.h):
// the mapping convention on the axes, the density integrating to 1 over the sphere, samples whose density is
// the density of their direction, texels drawn in proportion to luminance x sin(theta), and bad maps refused.
// shading_functions_test.cpp carries these functions over to the GPU.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "environment.h"
#include "random.h"
#include "scene/environment_map.h"
#include "scene/scene_error.h"
#include "support/sphere_quadrature.h"

namespace vkrt {
namespace {

// A map whose texel (x, y) has a radiance that names it: red x + 1, green y + 1, blue 1 (with a spread of
// luminance, so the distribution is far from uniform).
EnvironmentMap namedTexels(int width, int height, double rotationDegrees) {
    std::vector<glm::vec3> texels;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) texels.push_back(glm::vec3(x + 1, y + 1, 1.0f));
    }
    return makeEnvironmentMap("named", width, height, texels, rotationDegrees, 1.0);
}

// The texel (x, y) a world direction sees.
glm::ivec2 texelSeen(const EnvironmentTables& tables, glm::dvec3 direction) {
    const glm::dvec3 radiance = shading::environmentRadiance(tables, direction);
    return {static_cast<int>(radiance.x) - 1, static_cast<int>(radiance.y) - 1};
}

TEST(Environment, AxesSeeTheTexelsOfBlendersConvention) {
    // 63 x 31 texels: the centre column and row are texel centres, so no axis falls on a texel edge.
    const EnvironmentMap map = namedTexels(63, 31, 0.0);
    const EnvironmentTables tables(map);
    // u = 0.5 + atan2(z, x) / 2 pi, v = acos(y) / pi (top row +Y).
    EXPECT_EQ(texelSeen(tables, {0, 1, 0}).y, 0);                     // zenith: the top row
    EXPECT_EQ(texelSeen(tables, {0, -1, 0}).y, 30);                   // nadir: the bottom row
    EXPECT_EQ(texelSeen(tables, {1, 0, 0}), glm::ivec2(31, 15));      // +X: the centre
    EXPECT_EQ(texelSeen(tables, {0, 0, -1}), glm::ivec2(15, 15));     // -Z: u = 0.25
    EXPECT_EQ(texelSeen(tables, {0, 0, 1}), glm::ivec2(47, 15));      // +Z: u = 0.75
    EXPECT_EQ(texelSeen(tables, {-1, 0, -1e-3}), glm::ivec2(0, 15));  // -X: the seam, just left of it
    EXPECT_EQ(texelSeen(tables, {-1, 0, 1e-3}), glm::ivec2(62, 15));  // and just right of it
    EXPECT_EQ(texelSeen(tables, {0, 1, -1e-3}).y, 0);
    EXPECT_EQ(texelSeen(tables, {1, 1, 0}), glm::ivec2(31, 7));  // 45 degrees up: v = 0.25
}

TEST(Environment, RotationTurnsTheMapAboutY) {
    // Turned by 90 degrees, right-handed about +Y: what was at +Z (u = 0.75) is now seen at +X, and what
    // was at +X (the centre) at -Z.
    const EnvironmentMap turned = namedTexels(63, 31, 90.0);
    const EnvironmentTables tables(turned);
    EXPECT_EQ(texelSeen(tables, {1, 0, 0}), glm::ivec2(47, 15));
    EXPECT_EQ(texelSeen(tables, {0, 0, -1}), glm::ivec2(31, 15));
    EXPECT_EQ(texelSeen(tables, {0, 1, 0}).y, 0);
    // Direction and (u, v) are inverses of each other under rotation.
    const shading::EnvironmentMapInfo info = environmentMapInfo(turned);
    for (glm::dvec2 uv : {glm::dvec2(0.1, 0.2), glm::dvec2(0.7, 0.55), glm::dvec2(0.93, 0.9)}) {
        const glm::dvec2 back = shading::environmentUv(info, shading::environmentDirection(info, uv));
        EXPECT_NEAR(back.x, uv.x, 1e-12);
        EXPECT_NEAR(back.y, uv.y, 1e-12);
    }
}

TEST(Environment, DensityIntegratesToOneOverTheSphere) {
    const EnvironmentMap map = namedTexels(16, 8, 30.0);
    const EnvironmentTables tables(map);
    // 20 x 20 cells per texel, by the solid-angle element: independent of the Jacobian the density divides
    // by.
    const double integral = test::integrateOverSphere(
        160, 320, [&](const glm::dvec3& d) { return shading::environmentPdf(tables, d); });
    EXPECT_NEAR(integral, 1.0, 1e-3);
}

TEST(Environment, SamplesCarryTheDensityAndRadianceOfTheirDirection) {
    const EnvironmentMap map = namedTexels(16, 8, 30.0);
    const EnvironmentTables tables(map);
    for (uint32_t i = 0; i < 4096; ++i) {
        const double u1 = vkrtRandom(1, i, 0, 0), u2 = vkrtRandom(1, i, 0, 1);
        const shading::EnvironmentSample s = shading::sampleEnvironment(tables, u1, u2);
        ASSERT_GT(s.pdf, 0.0) << i;
        EXPECT_NEAR(glm::length(s.direction), 1.0, 1e-12);
        EXPECT_NEAR(shading::environmentPdf(tables, s.direction), s.pdf, 1e-9 * s.pdf) << i;
        EXPECT_EQ(shading::environmentRadiance(tables, s.direction), s.radiance) << i;
    }
}

TEST(Environment, TexelsAreDrawnByLuminanceTimesSinTheta) {
    const int width = 8, height = 4;
    const EnvironmentMap map = namedTexels(width, height, 0.0);
    const EnvironmentTables tables(map);
    std::vector<double> expected(width * height), drawn(width * height, 0.0);
    double total = 0.0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            expected[y * width + x] =
                shading::luminance(glm::dvec3(x + 1, y + 1, 1)) * std::sin(M_PI * (y + 0.5) / height);
            total += expected[y * width + x];
        }
    }
    const uint32_t samples = 1 << 18;
    for (uint32_t i = 0; i < samples; ++i) {
        const shading::EnvironmentSample s =
            shading::sampleEnvironment(tables, vkrtRandom(2, i, 0, 0), vkrtRandom(2, i, 0, 1));
        const glm::dvec3 r = s.radiance;
        drawn[(static_cast<int>(r.y) - 1) * width + static_cast<int>(r.x) - 1] += 1.0 / samples;
    }
    for (int i = 0; i < width * height; ++i) {
        const double p = expected[i] / total;
        // Five standard deviations of a binomial count.
        EXPECT_NEAR(drawn[i], p, 5.0 * std::sqrt(p * (1.0 - p) / samples)) << "texel " << i;
    }
}

TEST(Environment, DarkRowsAndBlackMapsStaySampleable) {
    // A map black but for one texel: every sample lands on it. A black map samples uniformly, finitely.
    std::vector<glm::vec3> texels(8 * 4, glm::vec3(0.0f));
    texels[2 * 8 + 5] = glm::vec3(3.0f);
    const EnvironmentMap spot = makeEnvironmentMap("spot", 8, 4, texels, 0.0, 2.0);
    const EnvironmentTables spotTables(spot);
    const EnvironmentMap black = makeEnvironmentMap("black", 8, 4, std::vector<glm::vec3>(32), 0.0, 1.0);
    const EnvironmentTables blackTables(black);
    for (uint32_t i = 0; i < 256; ++i) {
        const double u1 = vkrtRandom(3, i, 0, 0), u2 = vkrtRandom(3, i, 0, 1);
        const shading::EnvironmentSample s = shading::sampleEnvironment(spotTables, u1, u2);
        EXPECT_EQ(s.radiance, glm::dvec3(6.0));  // strength 2 applied
        const shading::EnvironmentSample b = shading::sampleEnvironment(blackTables, u1, u2);
        EXPECT_TRUE(std::isfinite(b.pdf) && b.pdf > 0.0);
        EXPECT_EQ(b.radiance, glm::dvec3(0.0));
    }
}

TEST(Environment, UnusableMapsAreSceneErrors) {
    const std::vector<glm::vec3> one(1, glm::vec3(1.0f));
    EXPECT_THROW(makeEnvironmentMap("empty", 0, 0, {}, 0.0, 1.0), SceneError);
    EXPECT_THROW(makeEnvironmentMap("short", 2, 1, one, 0.0, 1.0), SceneError);
    for (float bad : {-1.0f, NAN, INFINITY}) {
        try {
            makeEnvironmentMap("bad.exr", 1, 1, {glm::vec3(0.5f, bad, 0.5f)}, 0.0, 1.0);
            ADD_FAILURE() << bad << " accepted";
        } catch (const SceneError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("bad.exr: texel (0, 0)", 0), 0u) << e.what();
        }
    }
}

}  // namespace
}  // namespace vkrt
