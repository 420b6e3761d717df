// The path integrator against an independent renderer: Blender Cycles' images (tests/references/, made by
// tools/cycles_reference.py) of the Lambertian Cornell box, of a Lambertian, a mirror and a glass ball and of
// rough metal and glass balls under an HDR sky, of textured Lambertian surfaces under a point light and a
// sun, of Lambertian surfaces under spot lights and lit by emitters (one of them textured), of a scene seen
// through a thin lens and of moving objects blurred over a shutter, compared by 8x8-pixel blocks on the GPU
// and the CPU.
#include <algorithm>
#include <array>
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

// One of scenes/ with Cycles' image of it from tests/references/, set up as the command renders it at that
// image's size (`samplesPerPixel` and `seed`), under scenes/soft-sky.hdr where `underTheSky`.
struct CyclesComparison {
    Image cycles;
    Scene scene;
    FlatBvh bvh;
    RenderSetup setup;
};

Image softSky() {
    return readRadianceImage((test::sourceDir() / "scenes/soft-sky.hdr").string());
}

CyclesComparison prepare(const std::string& sceneName, const std::string& referenceName, bool underTheSky,
                         int samplesPerPixel, uint32_t seed) {
    CyclesComparison c;
    c.cycles = readImage((test::sourceDir() / "tests/references" / referenceName).string());
    c.scene = loadGltf((test::sourceDir() / "scenes" / sceneName).string());
    if (underTheSky) {
        const Image sky = softSky();
        c.scene.environment = makeEnvironmentMap("soft-sky.hdr", sky.width, sky.height, sky.pixels, 0.0, 1.0);
    }
    c.bvh = bvhFor(c.scene);
    const RenderRequest request = requestLike(c.cycles, samplesPerPixel, seed);
    addNeutralEnvironment(request, c.scene);
    c.setup = resolveRender(request, c.scene);
    return c;
}

// Both devices' images agree with Cycles' (expectAgreesWithCycles); returns them.
test::RenderPair expectBothDevicesAgree(const VulkanContext& context, const CyclesComparison& c) {
    EXPECT_EQ(c.setup.settings.integrator, Integrator::Path);
    EXPECT_TRUE(c.setup.warnings.empty());
    test::RenderPair renders = test::renderGpuAndCpu(context, c.scene, c.bvh, c.setup.camera,
                                                     c.setup.settings, test::shaderCacheDir());
    expectAgreesWithCycles(renders.gpu, c.cycles, "gpu");
    expectAgreesWithCycles(renders.cpu, c.cycles, "cpu");
    return renders;
}

// How the CPU reference's image of `scene` (changed from the comparison's, with `settings`) agrees with
// Cycles', printed as `what`: the comparison's check that it can tell.
BlockAgreement cpuAgreement(const CyclesComparison& c, const Scene& scene, const RenderSettings& settings,
                            const std::string& what) {
    const Image image = ReferenceRenderer(scene, c.bvh, c.setup.camera, settings).render().image;
    const BlockAgreement agreement = compareBlocks(image, c.cycles, 8, 0.03);
    std::cout << what << " (cpu): " << 100.0 * agreement.fractionWithin
              << "% of blocks within 3%, channel means / "
              << "Cycles " << agreement.meanRatio.x << " " << agreement.meanRatio.y << " "
              << agreement.meanRatio.z << "\n";
    return agreement;
}

RenderSettings withSamples(RenderSettings settings, int samplesPerPixel) {
    settings.samplesPerPixel = samplesPerPixel;
    return settings;
}

TEST_F(Gpu, PathTracedCornellBoxMatchesCycles) {
    // Cycles rendered 16,384 samples per pixel; vkrt renders 1024 with its defaults (the path integrator).
    const CyclesComparison c = prepare("cornell.gltf", "cornell-cycles.exr", false, 1024, 3);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: Whitted's ambient term in place of indirect light misses most blocks.
    RenderRequest whitted = requestLike(c.cycles, 64, 3);
    whitted.integrator = Integrator::Whitted;
    const RenderSetup classic = resolveRender(whitted, c.scene);
    EXPECT_LT(cpuAgreement(c, c.scene, classic.settings, "whitted").fractionWithin, 0.5);
}

// scenes/outdoor.gltf under scenes/soft-sky.hdr: the environment light's importance sampling and its mapping,
// a mirror, and glass with the exact Fresnel term, refraction and total internal reflection, against Cycles'
// Glossy and Glass BSDFs under the same map (16,384 samples per pixel there, 512 here).
TEST_F(Gpu, PathTracedOutdoorSceneMatchesCycles) {
    const CyclesComparison c = prepare("outdoor.gltf", "outdoor-cycles.exr", true, 512, 5);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: the sky turned by 90 degrees about +Y lights the balls from the side.
    Scene turned = c.scene;
    const Image sky = softSky();
    turned.environment = makeEnvironmentMap("soft-sky.hdr", sky.width, sky.height, sky.pixels, 90.0, 1.0);
    const BlockAgreement agreement =
        cpuAgreement(c, turned, withSamples(c.setup.settings, 64), "sky turned by 90 degrees");
    EXPECT_LT(agreement.fractionWithin, 0.6);
    EXPECT_LT(agreement.meanRatio.x, 0.97);
}

// scenes/rough.gltf under scenes/soft-sky.hdr: GGX reflection and transmission (white metal of roughness 0.3
// and 0.5, glass of roughness 0.15 and 0.3) against Cycles' multiple-scattering GGX (16,384 samples per pixel
// there, 512 here). Both keep the energy that single scattering loses, vkrt by its compensation and Cycles by
// its random walk, which spread it a little differently: up to 5% apart in a few blocks of the rougher balls.
TEST_F(Gpu, PathTracedRoughMetalAndGlassMatchCycles) {
    const CyclesComparison c = prepare("rough.gltf", "rough-cycles.exr", true, 512, 11);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: glTF's roughness taken as GGX's alpha (not its square root) misses many
    // blocks.
    Scene alpha = c.scene;
    for (Material& material : alpha.materials) material.roughness = std::sqrt(material.roughness);
    EXPECT_LT(
        cpuAgreement(c, alpha, withSamples(c.setup.settings, 128), "roughness taken as alpha").fractionWithin,
        0.9);
}

// scenes/tinted.gltf under scenes/soft-sky.hdr: Beer's law in glass balls (two smooth, one of roughness 0.1)
// against Cycles' Glass BSDF over a homogeneous Volume Absorption of the same coefficients (16,384 samples
// per pixel there, 512 here).
TEST_F(Gpu, PathTracedTintedGlassMatchesCycles) {
    const CyclesComparison c = prepare("tinted.gltf", "tinted-cycles.exr", true, 512, 15);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: the attenuation taken per unit length instead of per attenuation distance.
    Scene perUnit = c.scene;
    for (Material& material : perUnit.materials) {
        if (std::isfinite(material.attenuationDistance)) material.attenuationDistance = 1.0f;
    }
    EXPECT_LT(cpuAgreement(c, perUnit, withSamples(c.setup.settings, 64), "attenuation per unit length")
                  .fractionWithin,
              0.9);
}

// The share of 4x4-pixel blocks of `image` within 3% of Cycles' in every channel: blur moves light within an
// 8x8 block more than it changes the block's mean, so depth of field is judged on smaller blocks.
double fractionOfSmallBlocksWithin(const Image& image, const CyclesComparison& c, const std::string& what) {
    const double fraction = compareBlocks(image, c.cycles, 4, 0.03).fractionWithin;
    std::cout << what << ": " << 100.0 * fraction << "% of 4x4 blocks within 3%\n";
    return fraction;
}

// scenes/lens.gltf under scenes/soft-sky.hdr and a sun: depth of field, a thin lens of radius 0.08 focused on
// the second of four balls over a checkered floor, against Cycles' depth of field of the same radius and
// plane in focus (16,384 samples per pixel there, 256 here), also by 4x4-pixel blocks: 99.2% and 99.5% of
// them agree at two seeds (the CPU reference, 2026-12-07).
TEST_F(Gpu, PathTracedDepthOfFieldMatchesCycles) {
    const CyclesComparison c = prepare("lens.gltf", "lens-cycles.exr", true, 256, 17);
    ASSERT_EQ(c.setup.camera.aperture, 0.08);
    const auto [gpu, cpu] = expectBothDevicesAgree(context(), c);
    EXPECT_GE(fractionOfSmallBlocksWithin(gpu.image, c, "gpu"), 0.97);
    EXPECT_GE(fractionOfSmallBlocksWithin(cpu.image, c, "cpu"), 0.97);

    // The comparison can tell: the lens's radius taken for its diameter (80% of the 4x4 blocks agree), and
    // the focus a fifth nearer (82%), at the same samples.
    Camera halved = c.setup.camera;
    halved.aperture /= 2.0;
    Camera nearer = c.setup.camera;
    nearer.focusDistance *= 0.8;
    for (const auto& [camera, what] :
         {std::pair{halved, "the lens half as wide"}, std::pair{nearer, "the focus a fifth nearer"}}) {
        const Image image = ReferenceRenderer(c.scene, c.bvh, camera, c.setup.settings).render().image;
        EXPECT_LT(fractionOfSmallBlocksWithin(image, c, std::string(what) + " (cpu)"), 0.95) << what;
    }
}

// scenes/streaks.gltf: motion blur over a one-second shutter, a ball sliding two units (LINEAR translation)
// and a box turning 90 degrees as it moves, their shadows from a point light and a sun sweeping a textured
// floor, against Cycles' motion blur of the same shutter (its objects' transforms at 2^6 steps; 16,384
// samples per pixel there, 256 here), also by 4x4-pixel blocks.
TEST_F(Gpu, PathTracedMotionBlurMatchesCycles) {
    const CyclesComparison c = prepare("streaks.gltf", "streaks-cycles.exr", false, 256, 19);
    ASSERT_GT(c.scene.motionSegments, 0);
    const auto [gpu, cpu] = expectBothDevicesAgree(context(), c);
    EXPECT_GE(fractionOfSmallBlocksWithin(gpu.image, c, "gpu"), 0.97);
    EXPECT_GE(fractionOfSmallBlocksWithin(cpu.image, c, "cpu"), 0.97);

    // The comparison can tell: with the shutter closing at 0.9 of the way (each streak a tenth short) 88% of
    // the 4x4 blocks agree, closing halfway 80%, where the right shutter's image has them all (128 samples).
    const std::string path = (test::sourceDir() / "scenes/streaks.gltf").string();
    for (const auto& [close, what] :
         {std::pair{0.9, "the shutter closing at 0.9"}, std::pair{0.5, "the shutter closing halfway"}}) {
        LoadOptions options;
        options.shutter = std::array<double, 2>{0.0, close};
        const Scene shorter = loadGltf(path, options);
        const RenderSettings quick = withSamples(c.setup.settings, 128);
        const Image image = ReferenceRenderer(shorter, bvhFor(shorter), c.setup.camera, quick).render().image;
        EXPECT_LT(fractionOfSmallBlocksWithin(image, c, std::string(what) + " (cpu)"), 0.95) << what;
    }
}

// scenes/punctual.gltf: a point light and a sun (their units, falloff and shadows) over Lambertian surfaces
// whose textures are read at the nearest texel (which way up and round an image lies on a surface), against
// Cycles' point light and sun as tools/cycles_reference.py converts them (16,384 samples per pixel there, 256
// here).
TEST_F(Gpu, PathTracedPunctualLightsAndTexturesMatchCycles) {
    const CyclesComparison c = prepare("punctual.gltf", "punctual-cycles.exr", false, 256, 9);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: each of these, on the CPU at 64 samples, misses more than a tenth of the
    // blocks.
    const RenderSettings quick = withSamples(c.setup.settings, 64);
    Scene upsideDown = c.scene;  // every texture read with its rows the other way up
    for (Texture& texture : upsideDown.textures) {
        auto rows = std::make_shared<std::vector<uint8_t>>(texture.rgba->size());
        const size_t row = 4 * static_cast<size_t>(texture.width);
        for (int y = 0; y < texture.height; ++y) {
            std::copy_n(texture.rgba->begin() + static_cast<std::ptrdiff_t>(y * row), row,
                        rows->begin() + static_cast<std::ptrdiff_t>((texture.height - 1 - y) * row));
        }
        texture.rgba = rows;
    }
    EXPECT_LT(cpuAgreement(c, upsideDown, quick, "textures upside down").fractionWithin, 0.9);
    Scene dimmer = c.scene;  // the point light's intensity divided by pi, a usual slip between light units
    for (PunctualLight& light : dimmer.lights) {
        if (light.type == LightType::Point) light.intensity /= static_cast<float>(M_PI);
    }
    EXPECT_LT(cpuAgreement(c, dimmer, quick, "the point light a pi dimmer").fractionWithin, 0.9);
}

// scenes/spots.gltf: glTF's spot cone (the square of a ramp in the cosine off the axis, from the outer cone
// angle in to the inner) and range window, in a spot soft at its edge, one soft all the way in and of limited
// range, and a point light of short range, over Lambertian surfaces, against Cycles' spot and point lights
// given glTF's cone and range by tools/cycles_reference.py (16,384 samples per pixel there, 256 here).
TEST_F(Gpu, PathTracedSpotLightsAndRangesMatchCycles) {
    const CyclesComparison c = prepare("spots.gltf", "spots-cycles.exr", false, 256, 21);
    ASSERT_EQ(c.scene.lights.size(), 3u);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: the inner cones 3 degrees narrower (the warm one's; the cool one's is 0), the
    // outer cones 2 degrees wider, and the ranges left out, each on the CPU at 64 samples.
    const RenderSettings quick = withSamples(c.setup.settings, 64);
    Scene narrower = c.scene;
    for (PunctualLight& light : narrower.lights) {
        light.innerConeAngle = std::max(0.0f, light.innerConeAngle - static_cast<float>(M_PI / 60.0));
    }
    EXPECT_LT(cpuAgreement(c, narrower, quick, "the inner cones 3 degrees narrower").fractionWithin, 0.9);
    Scene wider = c.scene;
    for (PunctualLight& light : wider.lights) light.outerConeAngle += static_cast<float>(M_PI / 90.0);
    EXPECT_LT(cpuAgreement(c, wider, quick, "the outer cones 2 degrees wider").fractionWithin, 0.9);
    Scene unlimited = c.scene;
    for (PunctualLight& light : unlimited.lights) light.range = 0.0f;
    EXPECT_LT(cpuAgreement(c, unlimited, quick, "the ranges left out").fractionWithin, 0.9);
}

// scenes/lamps.gltf: light from emitters, one of them striped by its emissive texture, sampled as lights and
// met by paths (multiple importance sampling), against Cycles' Emission shaders (16,384 samples per pixel
// there, 512 here).
TEST_F(Gpu, PathTracedTexturedLampsMatchCycles) {
    const CyclesComparison c = prepare("lamps.gltf", "lamps-cycles.exr", false, 512, 13);
    expectBothDevicesAgree(context(), c);

    // The comparison can tell: the panel's texture left out (its factor alone), and every emitter 5% dimmer.
    const RenderSettings quick = withSamples(c.setup.settings, 64);
    Scene untextured = c.scene;
    for (Material& material : untextured.materials) material.emissiveTexture = TextureSlot{};
    EXPECT_LT(cpuAgreement(c, untextured, quick, "the emissive texture left out").fractionWithin, 0.9);
    Scene dimmer = c.scene;
    for (Material& material : dimmer.materials) material.emission *= 0.95f;
    const BlockAgreement agreement = cpuAgreement(c, dimmer, quick, "every emitter 5% dimmer");
    for (int channel = 0; channel < 3; ++channel) EXPECT_LT(agreement.meanRatio[channel], 0.98);
}

}  // namespace
}  // namespace vkrt
