// The counter-based generator: pinned values (the GPU must reproduce them bit for bit), range,
// uniformity and independence between dimensions.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "random.h"

namespace vkrt {
namespace {

TEST(Random, PinnedValues) {
    // Computed independently (Python, 32-bit masked arithmetic) from the definition in shaders/random.h.
    EXPECT_EQ(vkrtHash(1u), 0x688990c0u);
    EXPECT_EQ(vkrtRandomBits(0, 0, 0, 0), 0x352bad60u);
    EXPECT_EQ(vkrtRandomBits(0, 1, 0, 0), 0x7e8c5aabu);
    EXPECT_EQ(vkrtRandomBits(0, 0, 1, 0), 0x44dd4ff3u);
    EXPECT_EQ(vkrtRandomBits(0, 0, 0, 1), 0x05711438u);
    EXPECT_EQ(vkrtRandomBits(42, 12345, 678, 9), 0xde29bffbu);
    EXPECT_EQ(vkrtRandomBits(0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu), 0x8cd0dcd5u);
    EXPECT_EQ(vkrtRandom(42, 12345, 678, 9), static_cast<float>(0xde29bfu) / 16777216.0f);
}

TEST(Random, RangeIsHalfOpenUnitInterval) {
    for (uint32_t i = 0; i < 200000; ++i) {
        const float u = vkrtRandom(1, i, i * 7, i % 13);
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
    }
}

TEST(Random, UniformByChiSquare) {
    constexpr int bins = 64;
    constexpr int samples = 1 << 20;
    std::vector<int> counts(bins, 0);
    double sum = 0.0;
    for (uint32_t i = 0; i < samples; ++i) {
        const float u = vkrtRandom(3, i % 4096, i / 4096, 5);
        ++counts[static_cast<int>(u * bins)];
        sum += u;
    }
    double chi2 = 0.0;
    const double expected = static_cast<double>(samples) / bins;
    for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 110.0);  // 63 degrees of freedom: p < 0.0002 to fail by chance
    EXPECT_NEAR(sum / samples, 0.5, 0.002);
}

TEST(Random, DimensionsPixelsAndSamplesAreUncorrelated) {
    constexpr int n = 200000;
    auto correlation = [&](auto a, auto b) {
        double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
        for (uint32_t i = 0; i < n; ++i) {
            const double x = a(i), y = b(i);
            sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
        }
        const double cov = sab / n - sa / n * sb / n;
        return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
    };
    EXPECT_LT(std::abs(correlation([](uint32_t i) { return vkrtRandom(0, i, 0, 0); },
                                   [](uint32_t i) { return vkrtRandom(0, i, 0, 1); })),
              0.01);
    EXPECT_LT(std::abs(correlation([](uint32_t i) { return vkrtRandom(0, i, 0, 2); },
                                   [](uint32_t i) { return vkrtRandom(0, i + 1, 0, 2); })),
              0.01);
    EXPECT_LT(std::abs(correlation([](uint32_t i) { return vkrtRandom(0, 5, i, 2); },
                                   [](uint32_t i) { return vkrtRandom(0, 5, i + 1, 2); })),
              0.01);
    EXPECT_LT(std::abs(correlation([](uint32_t i) { return vkrtRandom(0, i, 0, 3); },
                                   [](uint32_t i) { return vkrtRandom(1, i, 0, 3); })),
              0.01);
}

TEST(Random, SobolSecondDimensionIsItsGeneratorMatrix) {
    // The definition: index bit k contributes the direction number v_k, v_0 = 2^31, v_(k+1) = v_k ^ (v_k >>
    // 1) (Pascal's triangle mod 2); random.h computes the same bits by a zeta transform.
    const auto byMatrix = [](uint32_t index) {
        uint32_t result = 0u, v = 0x80000000u;
        for (uint32_t bit = 0u; bit < 32u; ++bit, v ^= v >> 1u) {
            if ((index >> bit) & 1u) result ^= v;
        }
        return result;
    };
    EXPECT_EQ(vkrtSobol2(0u), 0u);
    EXPECT_EQ(vkrtSobol2(1u), 0x80000000u);
    EXPECT_EQ(vkrtSobol2(2u), 0xc0000000u);
    EXPECT_EQ(vkrtSobol2(3u), 0x40000000u);
    for (uint32_t bit = 0u; bit < 32u; ++bit) ASSERT_EQ(vkrtSobol2(1u << bit), byMatrix(1u << bit)) << bit;
    for (uint32_t index = 0u; index < (1u << 16); ++index)
        ASSERT_EQ(vkrtSobol2(index), byMatrix(index)) << index;
    uint32_t x = 1u;
    for (int i = 0; i < (1 << 16); ++i) {
        x = vkrtHash(x + 0x9e3779b9u);
        ASSERT_EQ(vkrtSobol2(x), byMatrix(x)) << x;
    }
    EXPECT_EQ(vkrtSobol2(0xffffffffu), byMatrix(0xffffffffu));
}

// The stratified numbers' bits as first defined, every hash of the chain from the seed and the pixel and the
// shuffled index reversed and reversed back, for the renderers' forms (the pixel's stream and pair root
// worked out once, no reversal undone) to reproduce bit for bit.
float stratifiedByDefinition(uint32_t seed, uint32_t pixel, uint32_t sample, uint32_t dimension,
                             uint32_t axis) {
    const uint32_t key = vkrtRandomBits(seed, pixel, 0xffffffffu, dimension);
    const uint32_t index = vkrtReverseBits(vkrtLaineKarras(vkrtReverseBits(sample), key));
    const uint32_t bits = axis == 0u ? vkrtReverseBits(index) : vkrtSobol2(index);
    return static_cast<float>((bits ^ vkrtHash(key ^ (0x68e31da4u + axis))) >> 8u) * 5.9604644775390625e-8f;
}

TEST(Random, PerPixelFormsDrawTheDefinitionsNumbers) {
    uint32_t x = 1u;
    for (int i = 0; i < 20000; ++i) {
        x = vkrtHash(x + static_cast<uint32_t>(i));
        const uint32_t seed = i % 7 == 0 ? 0xffffffffu : x & 0xffu, pixel = vkrtHash(x) % 5000000u;
        const uint32_t sample = i % 5 == 0 ? 16777215u : vkrtHash(x ^ 1u) % 4096u;
        const uint32_t dimension = vkrtHash(x ^ 2u) % (VKRT_DIM_NODE_BASE + 64u * VKRT_DIMS_PER_NODE);
        const uint32_t stream = vkrtPixelStream(seed, pixel), pairRoot = vkrtPairRoot(stream);
        ASSERT_EQ(vkrtStreamBits(stream, sample, dimension), vkrtRandomBits(seed, pixel, sample, dimension));
        ASSERT_EQ(vkrtSobol2OfReversed(x), vkrtSobol2(vkrtReverseBits(x))) << x;
        for (uint32_t axis : {0u, 1u}) {
            const float expected = stratifiedByDefinition(seed, pixel, sample, dimension, axis);
            ASSERT_EQ(vkrtStratifiedFrom(pairRoot, sample, dimension, axis), expected) << i;
            ASSERT_EQ(vkrtStratified(seed, pixel, sample, dimension, axis), expected) << i;
            ASSERT_EQ(vkrtLayered(stream, pairRoot, sample, dimension, axis), expected) << i;
        }
        const uint32_t layer = 2u + i % 62;
        const uint32_t layerBits =
            vkrtHash(vkrtRandomBits(seed, pixel, sample, dimension) ^ (layer * 0x9e3779b9u));
        ASSERT_EQ(vkrtLayered(stream, pairRoot, sample, dimension, layer),
                  static_cast<float>(layerBits >> 8u) * 5.9604644775390625e-8f);
        ASSERT_EQ(vkrtPixelJitterX(stream, sample),
                  static_cast<float>(
                      (vkrtReverseBits(sample) ^ vkrtRandomBits(seed, pixel, 0u, VKRT_DIM_PIXEL_X)) >> 8u) *
                      5.9604644775390625e-8f);
        ASSERT_EQ(vkrtPixelJitterY(stream, sample),
                  static_cast<float>(
                      (vkrtSobol2(sample) ^ vkrtRandomBits(seed, pixel, 0u, VKRT_DIM_PIXEL_Y)) >> 8u) *
                      5.9604644775390625e-8f);
    }
}

TEST(Random, StratifiedDimensionsAreNetsAtEveryPowerOfTwoAndDecorrelated) {
    // Every power-of-two prefix of a pixel's samples puts exactly one point in each of the 2^k elementary
    // intervals of every shape (a (0,k,2)-net), for several dimension pairs and pixels.
    for (uint32_t pixel : {0u, 77u, 123456u}) {
        for (uint32_t dimension : {VKRT_DIM_LENS_U, vkrtNodeDimension(3, VKRT_DIM_LOBE_U)}) {
            for (int k = 0; k <= 8; ++k) {
                const uint32_t n = 1u << k;
                for (int xBits = 0; xBits <= k; ++xBits) {
                    const uint32_t columns = 1u << xBits, rows = n / columns;
                    std::vector<int> cells(n, 0);
                    for (uint32_t s = 0; s < n; ++s) {
                        const float x = vkrtStratified(9, pixel, s, dimension, 0);
                        const float y = vkrtStratified(9, pixel, s, dimension, 1);
                        ++cells[static_cast<uint32_t>(y * rows) * columns +
                                static_cast<uint32_t>(x * columns)];
                    }
                    for (int c : cells)
                        ASSERT_EQ(c, 1) << "pixel " << pixel << " n " << n << " columns " << columns;
                }
            }
        }
    }
    // Different pairs are decorrelated: not the same points in a related order (an index XOR or an output
    // XOR would give |correlation| near 1 for some pixels; independent uniforms about 1 / sqrt(n)).
    double meanAbsCorrelation = 0.0;
    for (uint32_t pixel = 0; pixel < 64; ++pixel) {
        double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
        const int n = 256;
        for (uint32_t s = 0; s < n; ++s) {
            const double a = vkrtStratified(9, pixel, s, VKRT_DIM_LENS_U, 0);
            const double b =
                vkrtStratified(9, pixel, s, vkrtNodeDimension(0, VKRT_DIM_LIGHT(0, VKRT_DIM_LIGHT_U)), 0);
            sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
        }
        const double cov = sab / n - sa / n * sb / n;
        meanAbsCorrelation +=
            std::abs(cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n))) / 64;
    }
    EXPECT_LT(meanAbsCorrelation, 0.1);
}

TEST(Random, RayTreeNodesOwnDisjointDimensions) {
    // Node k's dimensions end before node k + 1's begin, and the pixel jitter comes first.
    EXPECT_GT(vkrtNodeDimension(0, 0), VKRT_DIM_PIXEL_Y);
    EXPECT_EQ(vkrtNodeDimension(1, 0), vkrtNodeDimension(0, VKRT_DIMS_PER_NODE - 1) + 1);
    // Every light sample's dimensions fit in a node's.
    EXPECT_LT(VKRT_DIM_LIGHT(VKRT_MAX_LIGHT_SAMPLES - 1, VKRT_DIM_LIGHT_ENVIRONMENT), VKRT_DIMS_PER_NODE);
    // The deepest node of a depth-24 tree (2^25 - 2) still fits in 32 bits.
    EXPECT_GT(vkrtNodeDimension((1u << 25) - 2, VKRT_DIMS_PER_NODE - 1), vkrtNodeDimension((1u << 24), 0));
}

}  // namespace
}  // namespace vkrt
