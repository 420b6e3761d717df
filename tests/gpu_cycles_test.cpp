// The path integrator against an independent renderer: Blender Cycles' images (tests/references/, made by
// tools/cycles_reference.py) of the Lambertian Cornell box, and of a Lambertian, a mirror and a glass ball under
// an HDR sky, compared by 8x8-pixel blocks on the GPU and the CPU.
#include <iostream>
#include <string>

#include <gtest/gtest.h>

#include "app/render_policy.h"
#include "image/image_io.h"
#include "image/image_metrics.h"
#include "scene/environment_map.h"
#include "scene/gltf_loader.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

// At least 95% of the 8x8 blocks of `result` agree with Cycles' image within 3% in every channel, and every
// channel's mean within 2%.
void expectAgreesWithCycles(const RenderResult& result, const Image& cycles, const std::string& which) {
    EXPECT_EQ(result.rays.nonFiniteSamples, 0u) << which;
    const BlockAgreement agreement = compareBlocks(result.image, cycles, 8, 0.03);
    EXPECT_GE(agreement.fractionWithin, 0.95) << which << ": worst block off by " << agreement.worstBlock;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(agreement.meanRatio[c], 1.0, 0.02) << which << ", channel " << c;
    std::cout << which << ": " << 100.0 * agreement.fractionWithin << "% of " << agreement.blocks
              << " blocks within 3% (worst " << 100.0 * agreement.worstBlock << "%), channel means / Cycles "
              << agreement.meanRatio.x << " " << agreement.meanRatio.y << " " << agreement.meanRatio.z << "\n";
}

// vkrt's request for the size of Cycles' image, with the command's defaults otherwise (the path integrator).
RenderRequest requestLike(const Image& cycles, int samplesPerPixel, uint32_t seed) {
    RenderRequest request;
    request.settings.width = cycles.width;
    request.height = cycles.height;
    request.settings.samplesPerPixel = samplesPerPixel;
    request.settings.seed = seed;
    return request;
}

TEST_F(Gpu, PathTracedCornellBoxMatchesCycles) {
    // Cycles rendered 16,384 samples per pixel; vkrt renders 1024 with its defaults (the path integrator).
    const Image cycles = readImage((test::sourceDir() / "tests/references/cornell-cycles.exr").string());
    Scene scene = loadGltf((test::sourceDir() / "scenes/cornell.gltf").string());
    const FlatBvh bvh = bvhFor(scene);
    const RenderRequest request = requestLike(cycles, 1024, 3);
    addNeutralEnvironment(request, scene);
    const RenderSetup setup = resolveRender(request, scene);
    ASSERT_EQ(setup.settings.integrator, Integrator::Path);
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
    expectAgreesWithCycles(gpu, cycles, "gpu");
    expectAgreesWithCycles(cpu, cycles, "cpu");

    // The comparison can tell: Whitted's ambient term in place of indirect light misses most blocks.
    RenderRequest whitted = request;
    whitted.integrator = Integrator::Whitted;
    whitted.settings.samplesPerPixel = 64;
    const RenderSetup classic = resolveRender(whitted, scene);
    const Image ambient = ReferenceRenderer(scene, bvh, classic.camera, classic.settings).render().image;
    const BlockAgreement agreement = compareBlocks(ambient, cycles, 8, 0.03);
    EXPECT_LT(agreement.fractionWithin, 0.5);
    std::cout << "whitted (cpu): " << 100.0 * agreement.fractionWithin << "% of blocks within 3%, channel means / "
              << "Cycles " << agreement.meanRatio.x << " " << agreement.meanRatio.y << " " << agreement.meanRatio.z
              << "\n";
}

// scenes/outdoor.gltf under scenes/soft-sky.hdr: the environment light's importance sampling and its mapping,
// a mirror, and glass with the exact Fresnel term, refraction and total internal reflection, against Cycles'
// Glossy and Glass BSDFs under the same map (16,384 samples per pixel there, 512 here).
TEST_F(Gpu, PathTracedOutdoorSceneMatchesCycles) {
    const Image cycles = readImage((test::sourceDir() / "tests/references/outdoor-cycles.exr").string());
    const Image sky = readRadianceImage((test::sourceDir() / "scenes/soft-sky.hdr").string());
    Scene scene = loadGltf((test::sourceDir() / "scenes/outdoor.gltf").string());
    scene.environment = makeEnvironmentMap("soft-sky.hdr", sky.width, sky.height, sky.pixels, 0.0, 1.0);
    const FlatBvh bvh = bvhFor(scene);
    const RenderSetup setup = resolveRender(requestLike(cycles, 512, 5), scene);
    ASSERT_EQ(setup.settings.integrator, Integrator::Path);
    ASSERT_TRUE(setup.warnings.empty());
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
    expectAgreesWithCycles(gpu, cycles, "gpu");
    expectAgreesWithCycles(cpu, cycles, "cpu");

    // The comparison can tell: the sky turned by 90 degrees about +Y lights the balls from the side.
    scene.environment = makeEnvironmentMap("soft-sky.hdr", sky.width, sky.height, sky.pixels, 90.0, 1.0);
    RenderSettings turnedSettings = setup.settings;
    turnedSettings.samplesPerPixel = 64;
    const Image turned = ReferenceRenderer(scene, bvh, setup.camera, turnedSettings).render().image;
    const BlockAgreement agreement = compareBlocks(turned, cycles, 8, 0.03);
    EXPECT_LT(agreement.fractionWithin, 0.6);
    EXPECT_LT(agreement.meanRatio.x, 0.97);
    std::cout << "sky turned by 90 degrees (cpu): " << 100.0 * agreement.fractionWithin << "% of blocks within 3%, "
              << "channel means / Cycles " << agreement.meanRatio.x << " " << agreement.meanRatio.y << " "
              << agreement.meanRatio.z << "\n";
}

}  // namespace
}  // namespace vkrt
