// The path integrator against closed forms, on the GPU and the CPU reference alike: an enclosure whose walls
// all emit and reflect diffusely has radiance 1 / (1 - A) everywhere, depth D sums D + 2 terms of that
// series, and a Lambertian sphere in a white furnace shows its albedo. And light through glass counted once,
// by paths and by Whitted's glossy lobes, whose light samples and traced rays share it by multiple importance
// sampling.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "image/image_metrics.h"
#include "scene/camera_selection.h"
#include "scene/environment_map.h"
#include "scene/scene_builder.h"
#include "shape_geometry.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

// A thin pane at height z over [-4, 4]^2 that transmits everything (index 1: no Fresnel reflection), of a
// material of its own.
void addClearPane(Scene& scene, float z) {
    Material glass = test::lambertian(1.0f);
    glass.transmission = 1.0f;
    glass.ior = 1.0f;
    glass.roughness = 0.0f;
    glass.specularFactor = 1.0f;
    scene.materials.push_back(glass);
    const uint32_t material = static_cast<uint32_t>(scene.materials.size() - 1);
    addFlatQuad(scene, {-4, -4, z}, {4, -4, z}, {4, 4, z}, {-4, 4, z}, material);
}

using test::meanRed;

// The cube [-1, 1]^3 with its faces turned inwards, every face of material 0.
void addInwardCube(Scene& scene) {
    const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                            {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    // Counter-clockwise seen from inside the cube.
    addFlatQuad(scene, c[0], c[1], c[2], c[3], 0);  // z = -1, facing +z
    addFlatQuad(scene, c[5], c[4], c[7], c[6], 0);  // z = +1, facing -z
    addFlatQuad(scene, c[4], c[0], c[3], c[7], 0);  // x = -1, facing +x
    addFlatQuad(scene, c[1], c[5], c[6], c[2], 0);  // x = +1, facing -x
    addFlatQuad(scene, c[4], c[5], c[1], c[0], 0);  // y = -1, facing +y
    addFlatQuad(scene, c[3], c[2], c[6], c[7], 0);  // y = +1, facing -y
}

// The cube [-1, 1]^3 seen from inside, its walls Lambertian of albedo `albedo` and emitting radiance 1.
Scene glowingCube(float albedo) {
    Scene scene;
    Material wall = test::lambertian(albedo);
    wall.emission = glm::vec3(1.0f);
    scene.materials.push_back(wall);
    addInwardCube(scene);
    finalizeScene(scene);
    return scene;
}

// Paths rendered from `position` looking along `forward` inside an enclosure whose walls all emit 1 and
// reflect `albedo` diffusely (32 x 32, 64 spp, depth 256, no ambient light) see 1 / (1 - albedo) everywhere,
// within 2% in every 8 x 8 block and 0.5% on average, on the GPU and the CPU. Returns both renders.
test::RenderPair expectGlowingEnclosure(const VulkanContext& context, const Scene& scene, glm::dvec3 position,
                                        glm::dvec3 forward, float albedo, const std::string& name) {
    const Camera camera = lookAtCamera(position, position + forward, 1.4);
    RenderSettings settings;
    settings.integrator = Integrator::Path;
    settings.maxDepth = 256;
    settings.ambient = glm::dvec3(0.0);
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 64;
    test::RenderPair pair =
        test::renderGpuAndCpu(context, scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
    Image exact(settings.width, settings.height);
    for (glm::vec3& p : exact.pixels) p = glm::vec3(static_cast<float>(1.0 / (1.0 - albedo)));
    for (const RenderResult* result : {&pair.gpu, &pair.cpu}) {
        const std::string which = std::string(result == &pair.gpu ? "gpu" : "cpu") + ", " + name;
        EXPECT_EQ(result->rays.nonFiniteSamples, 0u) << which;
        const BlockAgreement agreement = compareBlocks(result->image, exact, 8, 0.02, 0.0);
        EXPECT_EQ(agreement.fractionWithin, 1.0) << which << ": worst block off by " << agreement.worstBlock;
        EXPECT_NEAR(agreement.meanRatio.x, 1.0, 0.005) << which;
    }
    return pair;
}

TEST_F(Gpu, PathsInAGlowingEnclosureSeeOneOverOneMinusAlbedo) {
    // Every wall emits radiance 1 and reflects a fraction A diffusely: the radiance is 1 + A + A^2 + ... =
    // 1 / (1 - A) everywhere, 2 for A = 0.5 and 5 for A = 0.8. Light samples, cosine-sampled bounces, their
    // multiple importance sampling and Russian roulette all take part; any bias shows as a wrong level.
    for (const float albedo : {0.5f, 0.8f}) {
        // Corners, edges and three faces in view.
        const test::RenderPair renders =
            expectGlowingEnclosure(context(), glowingCube(albedo), {0.2, -0.1, 0.3}, {1.0, 0.7, 0.4}, albedo,
                                   "albedo " + std::to_string(albedo));
        for (const RenderResult* result : {&renders.gpu, &renders.cpu}) {
            // Paths went far beyond Whitted's depth: at A = 0.8 Russian roulette continues them with probability
            // about 0.8 per bounce.
            EXPECT_GT(result->rays.secondary, 3 * result->rays.primary) << "albedo " << albedo;
        }
    }
}

TEST_F(Gpu, PathsInAGlowingCsgCavitySeeOneOverOneMinusAlbedo) {
    // The same closed form inside a CSG solid: a box minus a sphere and a box poking out of it leaves a
    // cavity whose walls (the subtracted shapes' faces, turned inwards) emit 1 and reflect A. Every wall
    // lights every other across the cavity, all of it one primitive: light samples must reach the lamp's own
    // faces (its shadow rays crossing no wall on the way), or the level falls short.
    const float albedo = 0.5f;
    Scene scene;
    scene.materials.push_back(test::lambertian(0.5f));  // the outer box, never seen from inside
    Material wall = test::lambertian(albedo);
    wall.emission = glm::vec3(1.0f);
    scene.materials.push_back(wall);
    const glm::dmat4 pocket = glm::scale(glm::translate(glm::dmat4(1.0), {0.8, 0.0, 0.0}), {0.5, 0.4, 0.4});
    // Inside the outer box (bit 0) and neither subtracted shape: state 1.
    addSolid(scene,
             {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(2.0))),
              makeShape(VKRT_SHAPE_SPHERE, 1, glm::dmat4(1.0)), makeShape(VKRT_SHAPE_BOX, 1, pocket)},
             {1u << 1});
    finalizeScene(scene);
    // The pocket and the sphere around it.
    expectGlowingEnclosure(context(), scene, {0.1, 0.05, -0.2}, {1.0, 0.2, 0.3}, albedo, "CSG cavity");
}

TEST_F(Gpu, PathsInsideAGlowingSphereSeeOneOverOneMinusAlbedo) {
    // The same closed form inside a double-sided VKRT_sphere, whose points are the light samples' origins and
    // their targets at once. Seen from a point on the sphere, its sampler must take the inside (points
    // uniform by area), not the cone of a point outside, which it chose about half the time, the hit point
    // rounding to either side of the surface (the level came out 0.90 of 1 on the GPU and 0.90 on the CPU,
    // with 0.5 of emission and albedo 0.5). One-sided, the sphere emits outwards only: inside, every pixel is
    // black (it had leaked 0.05).
    const float albedo = 0.5f;
    for (const bool doubleSided : {true, false}) {
        Scene scene;
        Material wall = test::lambertian(albedo);
        wall.emission = glm::vec3(1.0f);
        wall.doubleSided = doubleSided;
        scene.materials.push_back(wall);
        scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        finalizeScene(scene);
        if (doubleSided) {
            expectGlowingEnclosure(context(), scene, {0.1, 0.05, -0.2}, {1.0, 0.2, 0.3}, albedo,
                                   "inside a sphere");
            continue;
        }
        Camera camera;
        camera.yfov = 1.4;
        RenderSettings settings;
        settings.integrator = Integrator::Path;
        settings.ambient = glm::dvec3(0.0);
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 16;
        const auto [gpu, cpu] =
            test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
        for (const RenderResult* result : {&gpu, &cpu}) {
            float brightest = 0.0f;
            for (const glm::vec3& p : result->image.pixels) brightest = std::max({brightest, p.x, p.y, p.z});
            EXPECT_EQ(brightest, 0.0f) << (result == &gpu ? "gpu" : "cpu") << ", one-sided";
        }
    }
}

TEST_F(Gpu, PathsStopAtTheMaximumDepth) {
    // Paths of at most D bounces (before Russian roulette starts) see the first D + 2 terms of the series,
    // 1 + A + ... + A^(D+1): every hit's emission, and at the last hit a light sample, which takes full weight
    // there since no bounce follows it. An unweighted or doubly weighted term would show.
    const float albedo = 0.5f;
    const Scene scene = glowingCube(albedo);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera;
    camera.yfov = 1.0;
    for (const int depth : {0, 1, 2}) {
        RenderSettings settings;
        settings.integrator = Integrator::Path;
        settings.maxDepth = depth;
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 256;
        const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
        double expected = 0.0;
        for (int k = 0; k <= depth + 1; ++k) expected += std::pow(albedo, k);
        for (const RenderResult* result : {&gpu, &cpu}) {
            double sum = 0.0;
            for (const glm::vec3& p : result->image.pixels) sum += p.x;
            // A missing or doubled term would be off by A^(D+1) / expected, at least 7% here.
            EXPECT_NEAR(sum / result->image.pixels.size(), expected, 0.015 * expected)
                << (result == &gpu ? "gpu" : "cpu") << ", depth " << depth;
        }
    }
}

TEST_F(Gpu, MultipleImportanceSamplingFarFromTheOriginMatchesClosedForm) {
    // A Lambertian floor of albedo 0.5 at x = 1e5 under a lamp, a sphere of radiance 1 and radius 6 whose
    // centre is 10 above it: the floor's radiance is 0.5 sin^2(alpha) = 0.18 (sin alpha = 6 / 10). New rays
    // there leave 0.38 above the floor (VKRT_RAY_OFFSET_EPSILON times the coordinates), while light samples
    // are drawn from the hit itself; the lamp's hit by a bounce ray was weighed by its density seen from the
    // offset origin, where it looks larger, and MIS made the floor 2.8% too bright (2.2 times at 1e6) on both
    // devices.
    constexpr float x = 1e5f;
    Scene scene;
    scene.materials.push_back(test::lambertian(0.5f));
    addFlatQuad(scene, {x - 10, -10, 0}, {x + 10, -10, 0}, {x + 10, 10, 0}, {x - 10, 10, 0}, 0);
    Material lamp = test::lambertian(0.0f);
    lamp.emission = glm::vec3(1.0f);
    scene.materials.push_back(lamp);
    scene.spheres.push_back({{x, 0.0f, 10.0f}, 6.0f, 1});
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera;  // straight down at the floor below the lamp's centre, from under the lamp
    camera.projection = Projection::Orthographic;
    camera.position = {x, 0.0, 1.0};
    camera.xmag = camera.ymag = 0.05;
    RenderSettings settings;
    settings.integrator = Integrator::Path;
    settings.maxDepth = 1;
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 256;
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    for (const RenderResult* result : {&gpu, &cpu}) {
        double sum = 0.0;
        for (const glm::vec3& p : result->image.pixels) sum += p.x;
        // What the offset still changes (the bounce ray meets the lamp from 0.38 nearer) is 0.7% here.
        EXPECT_NEAR(sum / result->image.pixels.size(), 0.18, 0.015 * 0.18)
            << (result == &gpu ? "gpu" : "cpu");
    }
}

TEST_F(Gpu, PathsInAWhiteFurnaceShowTheAlbedo) {
    // A Lambertian sphere of albedo 0.6 in a uniform environment of radiance 1: light samples of the
    // environment and cosine-sampled bounces that leave into it, weighed by MIS, sum to the albedo exactly (a
    // convex surface sees only the environment).
    Scene scene;
    scene.materials.push_back(test::lambertian(0.6f));
    scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
    scene.environment = makeEnvironmentMap("white", 8, 4, std::vector<glm::vec3>(32, glm::vec3(1.0f)), 0.0, 1.0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const Camera camera = test::sphereCamera();
    RenderSettings settings;
    settings.integrator = Integrator::Path;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = 64;
    const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    for (const RenderResult* result : {&gpu, &cpu}) {
        double sum = 0.0;
        int count = 0;
        for (int y = 0; y < settings.height; ++y) {
            for (int x = 0; x < settings.width; ++x) {
                const glm::dvec2 film((x + 0.5) / 12.0 - 1.0, (y + 0.5) / 12.0 - 1.0);
                if (glm::length(film) > 0.9) continue;  // the silhouette's pixels see the environment too
                sum += result->image.at(x, y).x;
                ++count;
            }
        }
        EXPECT_NEAR(sum / count, 0.6, 0.006) << (result == &gpu ? "gpu" : "cpu");
    }
}

TEST_F(Gpu, PathsCountLightThroughGlassOnce) {
    // A Lambertian floor under a glowing ceiling, seen through a thin pane that transmits everything (index 1:
    // no Fresnel reflection): the floor must look as it does without the pane. Light reaches it through the
    // pane along the paths that follow the pane's transmission; were shadow rays let through too, that light
    // would count twice.
    auto render = [&](bool pane) {
        Scene scene;
        scene.materials.push_back(test::lambertian(0.5f));
        Material glow = test::lambertian(0.0f);
        glow.emission = glm::vec3(1.0f);
        scene.materials.push_back(glow);
        addFlatQuad(scene, {-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}, 0);  // the floor, facing +z
        addFlatQuad(scene, {-4, -4, 2}, {-4, 4, 2}, {4, 4, 2}, {4, -4, 2}, 1);  // the ceiling, facing -z
        if (pane) addClearPane(scene, 1.0f);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        Camera camera = test::squareCamera();
        camera.position.z = 1.5;  // between the pane and the ceiling
        RenderSettings settings;
        settings.integrator = Integrator::Path;
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 256;
        return test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    };
    const auto open = render(false), glazed = render(true);
    auto mean = [](const Image& image) {
        double sum = 0.0;
        for (const glm::vec3& p : image.pixels) sum += p.x;
        return sum / static_cast<double>(image.pixels.size());
    };
    for (const bool gpu : {true, false}) {
        const double without = mean((gpu ? open.gpu : open.cpu).image), with = mean((gpu ? glazed.gpu : glazed.cpu).image);
        EXPECT_GT(without, 0.3) << "the ceiling lights the floor";
        EXPECT_NEAR(with, without, 0.02 * without) << (gpu ? "gpu" : "cpu");
    }
}

// A point light over a thin-walled pane of index 1 (no Fresnel reflection) tinted (0.8, 0.6, 0.4), over a
// Lambertian floor of albedo 0.5: paths light the floor through the pane, tinted, exactly as the closed form
// says, albedo / pi * I cos / r^2 * tint (no path finds a punctual light, and the shadow rays stopped at the
// pane: a window under the sun cast a black shadow). A volume's boundary still stops them: light refracted
// into glass arrives along a bent line.
TEST_F(Gpu, PathsLightThroughThinWalledPanesFromPunctualLights) {
    const glm::dvec3 tint(0.8, 0.6, 0.4);
    auto render = [&](float thickness) {
        Scene scene;
        scene.materials.push_back(test::lambertian(0.5f));
        addClearPane(scene, 0.5f);
        scene.materials.back().baseColor = glm::vec4(glm::vec3(tint), 1.0f);
        scene.materials.back().thickness = thickness;
        addFlatQuad(scene, {-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}, 0);  // the floor, facing +z
        PunctualLight light;
        light.position = {0.5, 0.5, 2.0};
        light.intensity = 4.0f;
        scene.lights.push_back(light);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        Camera camera = test::squareCamera();
        camera.position.z = 0.25;  // between the floor and the pane
        RenderSettings settings;
        settings.integrator = Integrator::Path;
        settings.width = settings.height = 8;
        settings.samplesPerPixel = 4;
        return test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    };
    const auto thin = render(0.0f), volume = render(0.1f);
    for (const bool gpu : {true, false}) {
        const Image& image = (gpu ? thin.gpu : thin.cpu).image;
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) {
                // The pixel's centre on the floor (the camera's film spans the unit square, its rows down y).
                const glm::dvec2 p((x + 0.5) / 8.0, 1.0 - (y + 0.5) / 8.0);
                const double r2 = glm::dot(p - 0.5, p - 0.5) + 4.0;
                const double irradiance = 4.0 * (2.0 / std::sqrt(r2)) / r2;
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(image.at(x, y)[c], 0.5 / M_PI * irradiance * tint[c],
                                0.01 * 0.5 / M_PI * irradiance)
                        << (gpu ? "gpu" : "cpu") << " at " << x << ", " << y << " channel " << c;
                }
            }
        }
        EXPECT_EQ(meanRed((gpu ? volume.gpu : volume.cpu).image), 0.0) << (gpu ? "gpu" : "cpu");
    }
}

// A rough glass ball inside a smooth glass ball of the same index, lit by a point light, with Whitted's
// distributed ray tracing: between media of one index there is no interface, so the inner ball is invisible
// and the image is the outer ball's alone. The light samples on the inner ball's surface took its lobe's
// Fresnel term at the ball's own index (1.5 against air) rather than the relative one (1): it showed the
// lamp's highlight.
TEST_F(Gpu, GlassInsideGlassOfTheSameIndexIsInvisible) {
    auto render = [&](bool inner) {
        Scene scene;
        Material glass;  // clear and smooth
        glass.baseColor = glm::vec4(1.0f);
        glass.metallic = 0.0f;
        glass.roughness = 0.0f;
        glass.transmission = 1.0f;
        glass.ior = 1.5f;
        glass.thickness = 1.0f;  // a volume
        scene.materials.push_back(glass);
        glass.roughness = 0.5f;
        scene.materials.push_back(glass);
        scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        if (inner) scene.spheres.push_back({glm::vec3(0.0f), 0.6f, 1});
        PunctualLight light;
        light.position = {1.0, 2.0, 4.0};
        light.intensity = 20.0f;
        scene.lights.push_back(light);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        RenderSettings settings;
        settings.integrator = Integrator::Whitted;
        settings.maxDepth = 24;
        settings.width = settings.height = 24;
        settings.samplesPerPixel = 4;
        return test::renderGpuAndCpu(context(), scene, bvh, test::sphereCamera(), settings,
                                     test::shaderCacheDir());
    };
    const auto alone = render(false), nested = render(true);
    for (const bool gpu : {true, false}) {
        const Image& a = (gpu ? alone.gpu : alone.cpu).image;
        const Image& b = (gpu ? nested.gpu : nested.cpu).image;
        double largest = 0.0;
        for (size_t i = 0; i < a.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c)
                largest = std::max(largest, double(std::abs(a.pixels[i][c] - b.pixels[i][c])));
        EXPECT_LT(largest, 2e-3) << (gpu ? "gpu" : "cpu");
    }
}

// A glossy floor (white metal of roughness 0.3) under a lamp, seen through a clear thin pane of index 1, with
// Whitted's distributed ray tracing: the floor must look as it does without the pane. Its traced reflections
// bring an area lamp's light through the pane; the light samples, which pass transmissive surfaces for the
// diffuse lobes' sake, must not light the traced lobe through it as well (that made it 25% too bright). A
// point light, which no traced ray finds, lights the traced lobe through the pane by its light samples alone,
// as every light does at depth 0, where no glossy ray is traced (holes alone had left the floor black there).
TEST_F(Gpu, WhittedGlossyLobesCountLightThroughGlassOnce) {
    auto render = [&](bool pane, bool pointLight, int maxDepth) {
        Scene scene;
        Material metal = test::lambertian(1.0f);
        metal.metallic = 1.0f;
        metal.roughness = 0.3f;
        scene.materials.push_back(metal);
        Material glow = test::lambertian(0.0f);
        glow.emission = glm::vec3(1.0f);
        scene.materials.push_back(glow);
        addFlatQuad(scene, {-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}, 0);  // the floor, facing +z
        if (pointLight) {
            PunctualLight light;
            light.position = {0.0, 0.0, 2.0};
            light.intensity = 4.0f;
            scene.lights.push_back(light);
        } else {
            addFlatQuad(scene, {-1, -1, 2}, {-1, 1, 2}, {1, 1, 2}, {1, -1, 2}, 1);  // the lamp, facing -z
        }
        if (pane) addClearPane(scene, 1.0f);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        Camera camera = test::squareCamera();
        camera.position = {0.3, -0.2, 0.5};  // under the pane, looking down at the floor
        RenderSettings settings;
        settings.integrator = Integrator::Whitted;
        settings.maxDepth = maxDepth;
        settings.ambient = glm::dvec3(0.0);
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 256;
        return test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    };
    for (const auto& [pointLight, maxDepth] :
         {std::pair{false, 8}, std::pair{true, 8}, std::pair{false, 0}}) {
        const auto open = render(false, pointLight, maxDepth), glazed = render(true, pointLight, maxDepth);
        for (const bool gpu : {true, false}) {
            const double without = meanRed((gpu ? open.gpu : open.cpu).image);
            const double with = meanRed((gpu ? glazed.gpu : glazed.cpu).image);
            EXPECT_GT(without, 0.05) << "the light lights the floor";
            EXPECT_NEAR(with, without, 0.03 * without)
                << (gpu ? "gpu" : "cpu") << (pointLight ? ", point light" : ", area lamp") << ", depth "
                << maxDepth;
        }
    }
}

// Whitted's branches below the throughput cut (1e-3) survive Russian roulette: a black glossy wall (F0 0.04,
// roughness 0.5) with a large lamp's highlight, seen from the other side through a thin pane that passes 2%
// (or all) of the light (and is not between the lamp and the wall), must come out 2% as bright. A hard cut
// dropped the traced lobe's share behind the dark pane while the light samples kept their weight against it
// (a review measured 0.0190 instead of 0.02).
TEST_F(Gpu, WhittedBranchesBelowTheCutKeepTheirShare) {
    const glm::vec3 y(0, 1, 0), towardsLamp(0.70710678f, 0, 0.70710678f),
        across(-0.70710678f, 0, 0.70710678f);
    auto render = [&](float paneAlbedo) {
        Scene scene;
        Material wall = test::lambertian(0.0f);
        wall.specularFactor = 1.0f;  // the dielectric's F0 of 0.04
        wall.roughness = 0.5f;
        scene.materials.push_back(wall);
        Material glow = test::lambertian(0.0f);
        glow.emission = glm::vec3(1.0f);
        scene.materials.push_back(glow);
        Material pane = test::lambertian(paneAlbedo);
        pane.transmission = 1.0f;
        pane.ior = 1.0f;
        pane.roughness = 0.0f;
        scene.materials.push_back(pane);
        addFlatQuad(scene, {-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}, 0);  // the wall, facing +z
        const glm::vec3 lamp = 3.0f * towardsLamp * 1.41421356f;  // (3, 0, 3), facing the wall's middle
        addFlatQuad(scene, lamp - 3.0f * y - 3.0f * across, lamp - 3.0f * y + 3.0f * across,
                    lamp + 3.0f * y + 3.0f * across, lamp + 3.0f * y - 3.0f * across, 1);
        const glm::vec3 glass(-1.5f, 0.0f, 1.5f);  // across the camera's view, on the other side
        addFlatQuad(scene, glass - y + towardsLamp, glass - y - towardsLamp, glass + y - towardsLamp,
                    glass + y + towardsLamp, 2);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        Camera camera = test::squareCamera();  // orthographic, 1 x 1
        camera.position = {-2.0, 0.0, 2.0};
        camera.forward = {0.70710678, 0.0, -0.70710678};
        camera.up = {0.70710678, 0.0, 0.70710678};
        camera.right = {0.0, -1.0, 0.0};
        RenderSettings settings;
        settings.integrator = Integrator::Whitted;
        settings.ambient = glm::dvec3(0.0);
        settings.width = settings.height = 16;
        settings.samplesPerPixel = 256;
        return test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    };
    const auto clear = render(1.0f), dark = render(0.02f);
    for (const bool gpu : {true, false}) {
        const double bright = meanRed((gpu ? clear.gpu : clear.cpu).image);
        const double dim = meanRed((gpu ? dark.gpu : dark.cpu).image);
        EXPECT_GT(bright, 0.01) << "the lamp's highlight is seen";
        EXPECT_NEAR(dim / bright, 0.02, 0.0004) << (gpu ? "gpu" : "cpu") << ": " << dim << " / " << bright;
    }
}

}  // namespace
}  // namespace vkrt
