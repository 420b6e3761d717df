// Analytic scenes with known answers, on the GPU and the CPU reference alike: a white furnace that never
// gains energy, a moving square's streak against velocity times shutter, and a sphere's silhouette against
// its analytic area.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/reference_renderer.h"
#include "scene/scene_builder.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

TEST_F(Gpu, WhiteFurnaceNeverGainsEnergy) {
    // A metal sphere with F0 = 1 (white base colour, metallic 1) of roughness 0, 0.25, 0.5 or 1 in a uniform
    // white environment (background and ambient radiance 1, no lights), traced by distributed Whitted ray
    // tracing. Energy never grows. Single-scattering GGX (the energy compensation off) weighs every traced
    // ray at most 1, so every pixel is at most 1, and loses what single scattering cannot return (about 60%
    // at roughness 1). The compensation (shaders/energy_compensation.h) returns it: the image is 1 on
    // average, within the tables' interpolation and the noise (single rays may weigh more than 1). The mirror
    // returns exactly 1 either way. tests/gpu_energy_test.cpp has the path integrator's metal and glass.
    for (float roughness : {0.0f, 0.25f, 0.5f, 1.0f}) {
        Scene scene;
        Material metal;
        metal.baseColor = glm::vec4(1.0f);
        metal.metallic = 1.0f;
        metal.roughness = roughness;
        scene.materials.push_back(metal);
        scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        const Camera camera = test::sphereCamera();
        for (const bool compensation : {false, true}) {
            RenderSettings settings;
            settings.width = settings.height = 24;
            settings.samplesPerPixel = 8;
            settings.ambient = glm::dvec3(1.0);
            settings.background = glm::dvec3(1.0);
            settings.energyCompensation = compensation;
            const auto [gpu, cpu] =
                test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
            for (const Image* image : {&gpu.image, &cpu.image}) {
                const std::string which = std::string(image == &gpu.image ? "gpu" : "cpu") + " roughness " +
                                          std::to_string(roughness) + (compensation ? ", compensated" : "");
                double sum = 0.0;
                for (const glm::vec3& p : image->pixels) {
                    if (!compensation) {
                        ASSERT_LE(std::max({p.x, p.y, p.z}), 1.0f + 1e-5f) << which;
                    }
                    if (roughness == 0.0f) {
                        ASSERT_NEAR(p.x, 1.0f, 1e-5f) << which;
                    }
                    sum += p.x;
                }
                const double mean = sum / static_cast<double>(image->pixels.size());
                if (compensation) {
                    EXPECT_NEAR(mean, 1.0, 0.01) << which;
                } else {
                    // The loss grows with roughness; the image must show it, not a constant.
                    const double lowest = roughness <= 0.25f ? 0.95 : roughness <= 0.5f ? 0.85 : 0.45;
                    EXPECT_GT(mean, lowest) << which;
                    if (roughness == 1.0f) {
                        EXPECT_LT(mean, 0.7) << which;
                    }
                }
            }
        }
    }
}

// An emitting square of side 0.2 moving 0.6 along x during the shutter, seen from straight ahead: its streak
// is side + velocity x shutter = 0.8 long, and where the square covers a point for a third of the shutter
// the streak's plateau is a third of its radiance.
TEST_F(Gpu, MotionBlurStreakIsVelocityTimesShutter) {
    Scene scene;
    Material lamp;
    lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    lamp.emission = glm::vec3(1.0f);
    scene.materials.push_back(lamp);
    addFlatQuad(scene, {-0.5f, -0.1f, 0.0f}, {-0.3f, -0.1f, 0.0f}, {-0.3f, 0.1f, 0.0f}, {-0.5f, 0.1f, 0.0f},
                0);
    for (const Triangle& t : scene.triangles) {
        const glm::vec3 shift(0.6f, 0.0f, 0.0f);
        scene.trianglePoses.push_back(
            {t.v0 + 0.5f * shift, t.v1 + 0.5f * shift, t.v2 + 0.5f * shift, t.material});
        scene.trianglePoses.push_back({t.v0 + shift, t.v1 + shift, t.v2 + shift, t.material});
    }
    scene.motionSegments = 2;
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings;
    settings.width = 160;
    settings.height = 16;
    settings.samplesPerPixel = 256;
    settings.ambient = glm::dvec3(0.0);
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.0, 0.0, 2.0};
    camera.xmag = 1.0;
    camera.ymag = 0.1;
    const Image gpu = renderGpu(scene, bvh, camera, settings).image;
    const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
    const double pixel = 2.0 / settings.width;
    for (const Image* image : {&gpu, &cpu}) {
        const char* which = image == &gpu ? "gpu" : "cpu";
        // Column means over the image's height (the square covers it all).
        std::vector<double> column(settings.width, 0.0);
        for (int x = 0; x < settings.width; ++x) {
            for (int y = 0; y < settings.height; ++y) column[x] += image->at(x, y).x / settings.height;
        }
        // Streak length: the integral of the profile over its peak is (side x velocity x shutter) / plateau
        // height... measured directly as the span of columns that saw any light.
        int first = -1, last = -1;
        double plateau = 0.0;
        int plateauCount = 0;
        for (int x = 0; x < settings.width; ++x) {
            const double centre = -1.0 + (x + 0.5) * pixel;
            if (column[x] > 1e-3) {
                if (first < 0) first = x;
                last = x;
            }
            if (centre > -0.25 && centre < 0.05) {  // fully inside the plateau [-0.3, 0.1]
                plateau += column[x];
                ++plateauCount;
            }
        }
        const double length = (last - first + 1) * pixel;
        EXPECT_NEAR(length, 0.8, 1.5 * pixel) << which;
        EXPECT_NEAR(plateau / plateauCount, 1.0 / 3.0, 0.01) << which;
        double total = 0.0;
        for (double c : column) total += c * pixel;
        EXPECT_NEAR(total, 0.2, 0.002) << which;  // the square's width, whatever the motion
    }
}

// An emitting sphere (radiance 1) against black: the image's mean times the film's area is the sphere's
// projected area. Orthographic: pi r^2. Perspective, on the axis at distance d: a disk of radius
// tan(asin(r/d)) on the film at distance 1.
TEST_F(Gpu, SphereSilhouetteMatchesItsAnalyticArea) {
    Scene scene;
    Material lamp;
    lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    lamp.emission = glm::vec3(1.0f);
    scene.materials.push_back(lamp);
    const double radius = 0.6;
    scene.spheres.push_back({glm::vec3(0.0f), static_cast<float>(radius), 0});
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings;
    settings.width = settings.height = 96;
    settings.samplesPerPixel = 64;
    settings.ambient = glm::dvec3(0.0);
    settings.maxDepth = 0;

    Camera orthographic;
    orthographic.projection = Projection::Orthographic;
    orthographic.position = {0.0, 0.0, 5.0};
    orthographic.xmag = orthographic.ymag = 1.0;
    Camera perspective;
    perspective.position = {0.0, 0.0, 3.0};
    perspective.yfov = 0.6;
    const double tanHalf = std::tan(0.3), tanAlpha = std::tan(std::asin(radius / 3.0));
    struct Case {
        const char* name;
        Camera camera;
        double expectedFraction;
    };
    for (const Case& c :
         {Case{"orthographic", orthographic, M_PI * radius * radius / 4.0},
          Case{"perspective", perspective, M_PI * tanAlpha * tanAlpha / (4.0 * tanHalf * tanHalf)}}) {
        const Image gpu = renderGpu(scene, bvh, c.camera, settings).image;
        const Image cpu = ReferenceRenderer(scene, bvh, c.camera, settings).render().image;
        for (const Image* image : {&gpu, &cpu}) {
            double sum = 0.0;
            for (const glm::vec3& p : image->pixels) sum += p.x;
            const double fraction = sum / static_cast<double>(image->pixels.size());
            EXPECT_NEAR(fraction, c.expectedFraction, 0.002 * c.expectedFraction)
                << c.name << (image == &gpu ? " gpu" : " cpu");
        }
    }
}

}  // namespace
}  // namespace vkrt
