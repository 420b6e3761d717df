// The path integrator against an independent renderer: Blender Cycles' image of the Lambertian Cornell box
// (tests/references/, made by tools/cycles_reference.py), compared by 8x8-pixel blocks on the GPU and the CPU.
#include <iostream>
#include <string>

#include <gtest/gtest.h>

#include "app/render_policy.h"
#include "image/image_io.h"
#include "image/image_metrics.h"
#include "scene/gltf_loader.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

TEST_F(Gpu, PathTracedCornellBoxMatchesCycles) {
    // Cycles rendered 16,384 samples per pixel; vkrt renders 1024 with its defaults (the path integrator). At
    // least 95% of the 8x8 blocks agree within 3% in every channel, and every channel's mean within 2%.
    const Image cycles = readImage((test::sourceDir() / "tests/references/cornell-cycles.exr").string());
    Scene scene = loadGltf((test::sourceDir() / "scenes/cornell.gltf").string());
    const FlatBvh bvh = bvhFor(scene);
    RenderRequest request;
    request.settings.width = cycles.width;
    request.height = cycles.height;
    request.settings.samplesPerPixel = 1024;
    request.settings.seed = 3;
    addNeutralEnvironment(request, scene);
    const RenderSetup setup = resolveRender(request, scene);
    ASSERT_EQ(setup.settings.integrator, Integrator::Path);
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
    for (const RenderResult* result : {&gpu, &cpu}) {
        const std::string which = result == &gpu ? "gpu" : "cpu";
        EXPECT_EQ(result->rays.nonFiniteSamples, 0u) << which;
        const BlockAgreement agreement = compareBlocks(result->image, cycles, 8, 0.03);
        EXPECT_GE(agreement.fractionWithin, 0.95) << which << ": worst block off by " << agreement.worstBlock;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(agreement.meanRatio[c], 1.0, 0.02) << which << ", channel " << c;
        std::cout << which << ": " << 100.0 * agreement.fractionWithin << "% of " << agreement.blocks
                  << " blocks within 3% (worst " << 100.0 * agreement.worstBlock << "%), channel means / Cycles "
                  << agreement.meanRatio.x << " " << agreement.meanRatio.y << " " << agreement.meanRatio.z << "\n";
    }

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

}  // namespace
}  // namespace vkrt
