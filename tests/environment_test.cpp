// The environment map's shared functions in C++ (shaders/environment.h with host/scene/environment_map.h):
// the mapping convention on the axes, the density integrating to 1 over the sphere, samples whose density is
// the density of their direction, texels drawn in proportion to luminance x sin(theta) with a tenth spread by
// solid angle, on the random numbers' grid (scene/sampling_grid.h) however bright a texel, and bad maps
// refused. shading_functions_test.cpp carries these functions over to the GPU.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "environment.h"
#include "random.h"
#include "scene/environment_map.h"
#include "scene/sampling_grid.h"
#include "scene/scene_error.h"
#include "support/sphere_quadrature.h"

namespace vkrt {
namespace {

// The grid tables both renderers pick from (scene/sampling_grid.h).
TEST(SamplingGrid, EveryPositiveWeightGetsAStepAndTheRestGoInProportion) {
    // 16 steps: one to each of the three positive weights, and the 13 left 0 : 9.75 : 3.25, the running sums
    // rounded (1 + 9.75 = 10.75 -> 11.75 after the first's step, 12 rounded).
    EXPECT_EQ(gridCdf({0.0, 1e-30, 3.0, 0.0, 1.0}, 16), (std::vector<uint64_t>{0, 1, 12, 12, 16}));
    // Without weight, uniform; with more steps than a double holds apart at the end, still a step each.
    EXPECT_EQ(gridCdf({0.0, 0.0, 0.0, 0.0}, 16), (std::vector<uint64_t>{4, 8, 12, 16}));
    const uint64_t steps = uint64_t(1) << 48;
    const std::vector<uint64_t> wide = gridCdf({1.0, 1e-20, 1.0}, steps);
    EXPECT_LE(std::max(wide[0], steps / 2) - std::min(wide[0], steps / 2), 1u);
    EXPECT_EQ(wide[1] - wide[0], 1u);
    EXPECT_EQ(wide[2], steps);
    EXPECT_THROW(gridCdf(std::vector<double>(17, 1.0), 16), std::length_error);
}

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
        const shading::EnvironmentSample s =
            shading::sampleEnvironment(tables, u1, u2, vkrtRandom(1, i, 0, 2), vkrtRandom(1, i, 0, 3));
        ASSERT_GT(s.pdf, 0.0) << i;
        EXPECT_NEAR(glm::length(s.direction), 1.0, 1e-12);
        EXPECT_NEAR(shading::environmentPdf(tables, s.direction), s.pdf, 1e-9 * s.pdf) << i;
        EXPECT_EQ(shading::environmentRadiance(tables, s.direction), s.radiance) << i;
    }
}

TEST(Environment, TexelsAreDrawnByLuminanceAndATenthBySolidAngle) {
    const int width = 8, height = 4;
    const EnvironmentMap map = namedTexels(width, height, 0.0);
    const EnvironmentTables tables(map);
    // Luminance times sin(theta) for nine tenths of the samples, sin(theta) alone for a tenth.
    std::vector<double> byLuminance(width * height), bySolidAngle(width * height);
    double luminanceTotal = 0.0, solidAngleTotal = 0.0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const double sinTheta = std::sin(M_PI * (y + 0.5) / height);
            byLuminance[y * width + x] = shading::luminance(glm::dvec3(x + 1, y + 1, 1)) * sinTheta;
            bySolidAngle[y * width + x] = sinTheta;
            luminanceTotal += byLuminance[y * width + x];
            solidAngleTotal += sinTheta;
        }
    }
    std::vector<double> expected(width * height), drawn(width * height, 0.0);
    for (int i = 0; i < width * height; ++i)
        expected[i] = 0.9 * byLuminance[i] / luminanceTotal + 0.1 * bySolidAngle[i] / solidAngleTotal;
    const double total = 1.0;
    const uint32_t samples = 1 << 18;
    for (uint32_t i = 0; i < samples; ++i) {
        const shading::EnvironmentSample s =
            shading::sampleEnvironment(tables, vkrtRandom(2, i, 0, 0), vkrtRandom(2, i, 0, 1),
                                       vkrtRandom(2, i, 0, 2), vkrtRandom(2, i, 0, 3));
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
    // A map black but for one texel: nine tenths of the samples land on it, and the rest, spread by solid
    // angle, on black texels with a finite density. A black map samples uniformly, finitely.
    std::vector<glm::vec3> texels(8 * 4, glm::vec3(0.0f));
    texels[2 * 8 + 5] = glm::vec3(3.0f);
    const EnvironmentMap spot = makeEnvironmentMap("spot", 8, 4, texels, 0.0, 2.0);
    const EnvironmentTables spotTables(spot);
    const EnvironmentMap black = makeEnvironmentMap("black", 8, 4, std::vector<glm::vec3>(32), 0.0, 1.0);
    const EnvironmentTables blackTables(black);
    const uint32_t samples = 4096;
    uint32_t onTheSpot = 0;
    for (uint32_t i = 0; i < samples; ++i) {
        const double u1 = vkrtRandom(3, i, 0, 0), u2 = vkrtRandom(3, i, 0, 1);
        const shading::EnvironmentSample s = shading::sampleEnvironment(spotTables, u1, u2, 0.5, 0.5);
        EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.0);
        if (s.radiance == glm::dvec3(6.0))
            ++onTheSpot;  // strength 2 applied
        else
            EXPECT_EQ(s.radiance, glm::dvec3(0.0));
        const shading::EnvironmentSample b = shading::sampleEnvironment(blackTables, u1, u2, 0.5, 0.5);
        EXPECT_TRUE(std::isfinite(b.pdf) && b.pdf > 0.0);
        EXPECT_EQ(b.radiance, glm::dvec3(0.0));
    }
    // 0.9 and the spot's share of the spread (its row's sin(theta) over the 32 texels').
    const double sinTheta[4] = {std::sin(M_PI / 8), std::sin(3 * M_PI / 8), std::sin(5 * M_PI / 8),
                                std::sin(7 * M_PI / 8)};
    const double expected =
        0.9 + 0.1 * sinTheta[2] / (8.0 * (sinTheta[0] + sinTheta[1] + sinTheta[2] + sinTheta[3]));
    EXPECT_NEAR(static_cast<double>(onTheSpot) / samples, expected, 5.0 * std::sqrt(0.1 * 0.9 / samples));
}

// A map with a sky of radiance 1 over the upper half and, below the horizon, one texel 1e12 times as bright:
// the whole sky weighs about 1e-9 of the sun.
EnvironmentMap skyAndSun(int width, int height) {
    std::vector<glm::vec3> texels(static_cast<size_t>(width) * height, glm::vec3(0.0f));
    for (int i = 0; i < width * height / 2; ++i) texels[i] = glm::vec3(1.0f);
    texels[static_cast<size_t>(height * 3 / 4) * width + width * 5 / 8] = glm::vec3(1e12f);
    return makeEnvironmentMap("sky and sun", width, height, texels, 0.0, 1.0);
}

TEST(Environment, TablesStateExactProbabilitiesOnTheRandomNumbersGrid) {
    // Every cumulative probability is a whole number of steps of 2^-24, so it is exact in a float and the
    // GPU's tables are the CPU's; every texel and row gets at least one step, however bright the sun beside
    // it (with tables of real sums in float, the sky's rows were all given probability 0 on the GPU, and with
    // 24-bit random numbers almost never drawn on the CPU).
    const EnvironmentMap map = skyAndSun(64, 32);
    const EnvironmentDistribution d = EnvironmentDistribution::build(map);
    auto onGrid = [](double cdf) {
        const double steps = cdf * VKRT_RANDOM_STEPS;
        return steps == std::floor(steps) && static_cast<double>(static_cast<float>(cdf)) == cdf;
    };
    for (size_t y = 0; y < d.rowCdf.size(); ++y) {
        EXPECT_TRUE(onGrid(d.rowCdf[y])) << "row " << y;
        EXPECT_GT(d.rowCdf[y], y > 0 ? d.rowCdf[y - 1] : 0.0) << "row " << y;
        for (size_t x = 0; x < 64; ++x) {
            const double cdf = d.columnCdf[y * 64 + x];
            EXPECT_TRUE(onGrid(cdf)) << "texel " << x << ", " << y;
            EXPECT_GT(cdf, x > 0 ? d.columnCdf[y * 64 + x - 1] : 0.0) << "texel " << x << ", " << y;
        }
    }
    EXPECT_EQ(d.rowCdf.back(), 1.0);
    // The spread over the sphere gives the sky (the upper half) about half of its tenth of the samples.
    EXPECT_NEAR(d.rowCdf[15], 0.05, 0.005);
}

TEST(Environment, SamplesOfADimTexelCoverAllOfIt) {
    // 2048 x 1024 texels: in the sun's row the spread gives each other texel a step or two, so u's remainder
    // in them is 0 or one half. The fine parts carry the point on over the whole texel, and a sample's
    // density is still its direction's.
    const int width = 2048, height = 1024, row = 768, column = 10;
    const EnvironmentMap map = skyAndSun(width, height);
    const EnvironmentTables tables(map);
    const uint32_t first = row * width;
    const double below = tables.environmentRowCdf(row - 1);
    const double texelBelow = tables.environmentColumnCdf(first + column - 1);
    const double texelProbability = tables.environmentColumnCdf(first + column) - texelBelow;
    const uint32_t steps = static_cast<uint32_t>(std::lround(texelProbability * VKRT_RANDOM_STEPS));
    ASSERT_GE(steps, 1u);
    ASSERT_LE(steps, 2u);
    double least = 1.0, most = 0.0;
    for (uint32_t i = 0; i < 64; ++i) {
        // The first step of the row, each step of the texel within it, and fine parts spread over [0, 1).
        const double fine1 = (i + 0.5) / 64.0, fine2 = ((i * 37) % 64 + 0.5) / 64.0;
        const shading::EnvironmentSample s = shading::sampleEnvironment(
            tables, below, texelBelow + (i % steps) * VKRT_RANDOM_STEP, fine1, fine2);
        ASSERT_GT(s.pdf, 0.0);
        EXPECT_NEAR(shading::environmentPdf(tables, s.direction), s.pdf, 1e-9 * s.pdf);
        const glm::dvec2 uv = shading::environmentUv(environmentMapInfo(map), s.direction);
        EXPECT_EQ(static_cast<int>(uv.x * width), column);
        EXPECT_EQ(static_cast<int>(uv.y * height), row);
        least = std::min(least, uv.x * width - column);
        most = std::max(most, uv.x * width - column);
    }
    EXPECT_LT(least, 0.05);
    EXPECT_GT(most, 0.95);
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
