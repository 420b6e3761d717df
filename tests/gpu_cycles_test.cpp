// The path integrator against an independent renderer: Blender Cycles' images (tests/references/, made by
// tools/cycles_reference.py) of the Lambertian Cornell box, of a Lambertian, a mirror and a glass ball under
// an HDR sky, and of textured Lambertian surfaces under a point light and a sun, compared by 8x8-pixel blocks
// on the GPU and the CPU.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

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

// scenes/rough.gltf under scenes/soft-sky.hdr: GGX reflection and transmission (white metal of roughness 0.3
// and 0.5, glass of roughness 0.15 and 0.3) against Cycles' multiple-scattering GGX (16,384 samples per pixel
// there, 512 here). Both keep the energy that single scattering loses, vkrt by its compensation and Cycles by
// its random walk, which spread it a little differently: up to 5% apart in a few blocks of the rougher balls.
TEST_F(Gpu, PathTracedRoughMetalAndGlassMatchCycles) {
    const Image cycles = readImage((test::sourceDir() / "tests/references/rough-cycles.exr").string());
    const Image sky = readRadianceImage((test::sourceDir() / "scenes/soft-sky.hdr").string());
    Scene scene = loadGltf((test::sourceDir() / "scenes/rough.gltf").string());
    scene.environment = makeEnvironmentMap("soft-sky.hdr", sky.width, sky.height, sky.pixels, 0.0, 1.0);
    const FlatBvh bvh = bvhFor(scene);
    const RenderSetup setup = resolveRender(requestLike(cycles, 512, 11), scene);
    ASSERT_EQ(setup.settings.integrator, Integrator::Path);
    ASSERT_TRUE(setup.warnings.empty());
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
    expectAgreesWithCycles(gpu, cycles, "gpu");
    expectAgreesWithCycles(cpu, cycles, "cpu");

    // The comparison can tell: glTF's roughness taken as GGX's alpha (not its square root) misses many
    // blocks.
    Scene alpha = scene;
    for (Material& material : alpha.materials) material.roughness = std::sqrt(material.roughness);
    RenderSettings quick = setup.settings;
    quick.samplesPerPixel = 128;
    const Image image = ReferenceRenderer(alpha, bvh, setup.camera, quick).render().image;
    const BlockAgreement agreement = compareBlocks(image, cycles, 8, 0.03);
    EXPECT_LT(agreement.fractionWithin, 0.9);
    std::cout << "roughness taken as alpha (cpu): " << 100.0 * agreement.fractionWithin
              << "% of blocks within 3%\n";
}

// scenes/punctual.gltf: a point light and a sun (their units, falloff and shadows) over Lambertian surfaces
// whose textures are read at the nearest texel (which way up and round an image lies on a surface), against
// Cycles' point light and sun as tools/cycles_reference.py converts them (16,384 samples per pixel there, 256
// here).
TEST_F(Gpu, PathTracedPunctualLightsAndTexturesMatchCycles) {
    const Image cycles = readImage((test::sourceDir() / "tests/references/punctual-cycles.exr").string());
    Scene scene = loadGltf((test::sourceDir() / "scenes/punctual.gltf").string());
    const FlatBvh bvh = bvhFor(scene);
    const RenderSetup setup = resolveRender(requestLike(cycles, 256, 9), scene);
    ASSERT_EQ(setup.settings.integrator, Integrator::Path);
    ASSERT_TRUE(setup.warnings.empty());
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
    expectAgreesWithCycles(gpu, cycles, "gpu");
    expectAgreesWithCycles(cpu, cycles, "cpu");

    // The comparison can tell: each of these, on the CPU at 64 samples, misses more than a tenth of the
    // blocks.
    RenderSettings quick = setup.settings;
    quick.samplesPerPixel = 64;
    const auto missed = [&](const Scene& changed, const char* what) {
        const Image image = ReferenceRenderer(changed, bvh, setup.camera, quick).render().image;
        const BlockAgreement agreement = compareBlocks(image, cycles, 8, 0.03);
        EXPECT_LT(agreement.fractionWithin, 0.9) << what;
        std::cout << what << " (cpu): " << 100.0 * agreement.fractionWithin << "% of blocks within 3%\n";
    };
    Scene upsideDown = scene;  // every texture read with its rows the other way up
    for (Texture& texture : upsideDown.textures) {
        auto rows = std::make_shared<std::vector<uint8_t>>(texture.rgba->size());
        const size_t row = 4 * static_cast<size_t>(texture.width);
        for (int y = 0; y < texture.height; ++y) {
            std::copy_n(texture.rgba->begin() + static_cast<std::ptrdiff_t>(y * row), row,
                        rows->begin() + static_cast<std::ptrdiff_t>((texture.height - 1 - y) * row));
        }
        texture.rgba = rows;
    }
    missed(upsideDown, "textures upside down");
    Scene dimmer = scene;  // the point light's intensity divided by pi, a usual slip between light units
    for (PunctualLight& light : dimmer.lights) {
        if (light.type == LightType::Point) light.intensity /= static_cast<float>(M_PI);
    }
    missed(dimmer, "the point light a pi dimmer");
}

}  // namespace
}  // namespace vkrt
