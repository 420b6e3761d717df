// The environment light (--environment) on the GPU and the CPU reference alike: camera rays along the six
// axes see the texels the mapping convention names; against closed forms, a Lambertian sphere in a uniform
// environment shows its albedo, an upward plane under a polar cap of half-angle t and radiance L shows
// r L sin^2 t with per-pixel noise under 10% at 16 spp, and a tilted plane under a turned map with one bright
// region shows the irradiance integrated by brute force, and a plane beside a sun 1e12 times as bright as its
// sky sees the sky. Also: multiple importance sampling keeps the mean, the GPU matches the reference on
// scenes/environment.gltf, lights of every kind at once add up to the renders lit by each alone, light from a
// map near float's limit scales with its strength, and scenes without an environment get neither its code nor
// its buffers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/render_policy.h"

#include "gpu/gpu_scene.h"
#include "image/image_io.h"
#include "scene/scene_builder.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/sphere_quadrature.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

EnvironmentMap mapOf(int width, int height, const std::function<glm::vec3(int, int)>& texel,
                     double rotationDegrees = 0.0) {
    std::vector<glm::vec3> texels;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) texels.push_back(texel(x, y));
    }
    return makeEnvironmentMap("test", width, height, texels, rotationDegrees, 1.0);
}

// An orthographic camera at `position` looking along `forward`, seeing a square of half-size `half`.
Camera orthographic(glm::dvec3 position, glm::dvec3 forward, glm::dvec3 up, double half) {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = position;
    camera.forward = glm::normalize(forward);
    camera.right = glm::normalize(glm::cross(camera.forward, up));
    camera.up = glm::cross(camera.right, camera.forward);
    camera.xmag = camera.ymag = half;
    return camera;
}

// A square of half-size `half` through the origin facing `normal`.
void addPlane(Scene& scene, glm::dvec3 normal, double half, uint32_t material) {
    const glm::dvec3 n = glm::normalize(normal);
    const glm::dvec3 a =
        glm::normalize(glm::cross(n, std::abs(n.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
    const glm::dvec3 b = glm::cross(n, a);
    auto corner = [&](double s, double t) { return glm::vec3(half * (s * a + t * b)); };
    addFlatQuad(scene, corner(-1, -1), corner(-1, 1), corner(1, 1), corner(1, -1), material);
}

RenderSettings darkSettings(int size, int spp) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = spp;
    settings.ambient = glm::dvec3(0.0);
    settings.background = glm::dvec3(0.25);  // replaced by the environment
    return settings;
}

// The mean and relative standard deviation of channel `c` over every pixel.
struct PixelStatistics {
    double mean;
    double relativeDeviation;
};
PixelStatistics statisticsOf(const Image& image, int c) {
    double sum = 0.0, squares = 0.0;
    for (const glm::vec3& p : image.pixels) {
        sum += p[c];
        squares += double(p[c]) * p[c];
    }
    const double n = static_cast<double>(image.pixels.size()), mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, squares / n - mean * mean)) / mean};
}

TEST_F(Gpu, CameraRaysAlongTheAxesSeeTheTexelsOfTheConvention) {
    // An empty scene under a map whose texel (x, y) has radiance (x + 1, y + 1, 1), turned by 90 degrees;
    // orthographic cameras look along the six axes, so every pixel sees the texel of that one direction
    // (docs/environment.md: u = 0.5 + atan2(z, x) / 2 pi, v = acos(y) / pi, looked up at R_y(-90) d).
    Scene scene;
    std::vector<glm::vec3> texels;
    for (int y = 0; y < 31; ++y) {
        for (int x = 0; x < 63; ++x) texels.push_back(glm::vec3(x + 1, y + 1, 1.0f));
    }
    scene.environment = makeEnvironmentMap("named", 63, 31, texels, 90.0, 1.0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    struct Axis {
        const char* name;
        glm::dvec3 forward, up;
        glm::ivec2 texel;  // x (-1: not checked), y
    };
    // Turned by 90 degrees: +X sees what the map holds at +Z (u = 0.75), -Z what it holds at +X (the centre).
    for (const Axis& axis :
         {Axis{"+X", {1, 0, 0}, {0, 1, 0}, {47, 15}}, Axis{"-Z", {0, 0, -1}, {0, 1, 0}, {31, 15}},
          Axis{"-X", {-1, 0, 0}, {0, 1, 0}, {15, 15}}, Axis{"+Z", {0, 0, 1}, {0, 1, 0}, {-1, 15}},
          Axis{"+Y", {0, 1, 0}, {0, 0, 1}, {-1, 0}}, Axis{"-Y", {0, -1, 0}, {0, 0, 1}, {-1, 30}}}) {
        const Camera camera = orthographic({0, 0, 0}, axis.forward, axis.up, 1.0);
        const test::RenderPair pair =
            test::renderGpuAndCpu(context(), scene, bvh, camera, darkSettings(2, 1), test::shaderCacheDir());
        for (const Image* image : {&pair.gpu.image, &pair.cpu.image}) {
            const glm::vec3 seen = image->at(1, 1);
            // +Z looks at the seam (u = 0 or 1) and the poles at every column: only the row is checked there.
            const char* device = image == &pair.gpu.image ? "gpu" : "cpu";
            if (axis.texel.x >= 0) {
                EXPECT_EQ(seen.x, float(axis.texel.x + 1)) << device << " " << axis.name;
            }
            EXPECT_EQ(seen.y, float(axis.texel.y + 1)) << device << " " << axis.name;
        }
    }
}

TEST_F(Gpu, LambertianSphereInAUniformEnvironmentShowsItsAlbedo) {
    Scene scene;
    scene.materials.push_back(test::lambertian(0.6f));
    scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
    scene.environment = mapOf(16, 8, [](int, int) { return glm::vec3(1.0f); });
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const Camera camera = orthographic({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 1.25);
    const int size = 32;
    const test::RenderPair pair =
        test::renderGpuAndCpu(context(), scene, bvh, camera, darkSettings(size, 16), test::shaderCacheDir());
    for (const Image* image : {&pair.gpu.image, &pair.cpu.image}) {
        const char* device = image == &pair.gpu.image ? "gpu" : "cpu";
        double sum = 0.0;
        int count = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const double px = 1.25 * (2.0 * (x + 0.5) / size - 1.0),
                             py = 1.25 * (2.0 * (y + 0.5) / size - 1.0);
                const double r = std::hypot(px, py);
                if (r > 1.2) {
                    EXPECT_EQ(image->at(x, y), glm::vec3(1.0f)) << device << ": rays that miss see the map";
                } else if (r < 0.85) {
                    sum += image->at(x, y).x;
                    ++count;
                }
            }
        }
        std::printf("%s: sphere of albedo 0.6 shows %.5f\n", device, sum / count);
        EXPECT_NEAR(sum / count, 0.6, 0.6 * 0.03) << device;
    }
}

TEST_F(Gpu, LightFromAnEnvironmentNearFloatsLimitScalesWithIt) {
    // Radiance is linear in the environment's strength, and a power of two scales every float operation
    // exactly: a sphere under a uniform map of strength 2^125 (4.3e37) renders 2^125 times the image at
    // strength
    // 1. Its pixels (about 0.6 L, one sample each: no pixel's sum nears float's limit) stay far below 3.4e38,
    // but a light sample's L / pdf (about 4 pi L) does not: the GPU lost such samples when it divided the
    // radiance by the density before the weights.
    const float strength = std::ldexp(1.0f, 125);
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        SCOPED_TRACE(integratorName(integrator));
        RenderSettings settings = darkSettings(16, 1);
        settings.integrator = integrator;
        std::vector<Image> gpu, cpu;
        for (const float radiance : {1.0f, strength}) {
            Scene scene;
            scene.materials.push_back(test::lambertian(0.6f));
            scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
            scene.environment = mapOf(16, 8, [&](int, int) { return glm::vec3(radiance); });
            finalizeScene(scene);
            // Every pixel sees the sphere: rays that miss would bring the map's radiance itself.
            const Camera camera = orthographic({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 0.6);
            const test::RenderPair pair = test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera,
                                                                settings, test::shaderCacheDir());
            EXPECT_EQ(pair.gpu.rays.nonFiniteSamples, 0u) << "strength " << radiance;
            EXPECT_EQ(pair.cpu.rays.nonFiniteSamples, 0u) << "strength " << radiance;
            gpu.push_back(pair.gpu.image);
            cpu.push_back(pair.cpu.image);
        }
        for (const auto* images : {&gpu, &cpu}) {
            const char* device = images == &gpu ? "gpu" : "cpu";
            EXPECT_NEAR(test::meanRed((*images)[0]), 0.6, 0.15) << device;  // one sample a pixel
            for (size_t i = 0; i < (*images)[0].pixels.size(); ++i) {
                const glm::vec3 dim = (*images)[0].pixels[i], bright = (*images)[1].pixels[i];
                ASSERT_NEAR(bright.x / strength, dim.x, dim.x * 1e-6) << device << " pixel " << i;
            }
        }
    }
}

TEST_F(Gpu, TheNeutralEnvironmentLightsAndIsSeenOnlyInReflections) {
    // A scene without lights gets the neutral environment (uniform radiance 1): a Lambertian sphere of albedo
    // 0.6 shows 0.6, a white mirror sphere reflects 1, and camera rays that miss see the background (0.25),
    // not the environment.
    for (const bool mirror : {false, true}) {
        Scene scene;
        Material material = test::lambertian(0.6f);
        if (mirror) {
            material.baseColor = glm::vec4(1.0f);
            material.metallic = 1.0f;
            material.roughness = 0.0f;
        }
        scene.materials.push_back(material);
        scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        finalizeScene(scene);
        ASSERT_TRUE(addNeutralEnvironment(RenderRequest{}, scene));
        const FlatBvh bvh = bvhFor(scene);
        const Camera camera = orthographic({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 1.25);
        const test::RenderPair pair =
            test::renderGpuAndCpu(context(), scene, bvh, camera, darkSettings(16, 16), test::shaderCacheDir());
        for (const Image* image : {&pair.gpu.image, &pair.cpu.image}) {
            EXPECT_EQ(image->at(0, 0), glm::vec3(0.25f)) << "rays that miss see the background";
            if (mirror) {
                EXPECT_NEAR(image->at(8, 8).x, 1.0, 1e-6);
                continue;
            }
            double sum = 0.0;  // the 6 x 6 pixels around the centre (16 samples each are noisy alone)
            for (int y = 5; y < 11; ++y) {
                for (int x = 5; x < 11; ++x) sum += image->at(x, y).x;
            }
            EXPECT_NEAR(sum / 36.0, 0.6, 0.6 * 0.03);
        }
    }
}

TEST_F(Gpu, TheNeutralEnvironmentIsNotSeenThroughClearGlass) {
    // Glass of index 1 reflects nothing and bends nothing: through it, as beside it, camera rays see the
    // background (0.25), not the neutral environment, whose light they once showed there (1), a solid sphere
    // and a thin-walled one alike, in both integrators.
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        for (const float thickness : {0.0f, 1.0f}) {
            SCOPED_TRACE(testing::Message() << integratorName(integrator) << ", thickness " << thickness);
            Scene scene;
            Material glass = test::lambertian(1.0f);
            glass.transmission = 1.0f;
            glass.ior = 1.0f;
            glass.roughness = 0.0f;
            glass.thickness = thickness;
            scene.materials.push_back(glass);
            scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
            finalizeScene(scene);
            ASSERT_TRUE(addNeutralEnvironment(RenderRequest{}, scene));
            const FlatBvh bvh = bvhFor(scene);
            const Camera camera = orthographic({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 1.25);
            RenderSettings settings = darkSettings(16, 4);
            settings.integrator = integrator;
            const test::RenderPair pair =
                test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
            for (const Image* image : {&pair.gpu.image, &pair.cpu.image}) {
                EXPECT_EQ(image->at(0, 0), glm::vec3(0.25f)) << "beside the sphere";
                EXPECT_NEAR(image->at(8, 8).x, 0.25, 1e-6) << "through the sphere";
            }
        }
    }
}

// An upward plane of albedo `albedo`, 2000 across, under `map`, seen from above over 2 x 2 around its centre,
// by both devices.
test::RenderPair renderPlaneUnder(const VulkanContext& context, EnvironmentMap map, double albedo,
                                  const RenderSettings& settings) {
    Scene scene;
    scene.materials.push_back(test::lambertian(static_cast<float>(albedo)));
    addPlane(scene, {0, 1, 0}, 1000.0, 0);
    scene.environment = std::move(map);
    finalizeScene(scene);
    const Camera camera = orthographic({0, 5, 0}, {0, -1, 0}, {0, 0, 1}, 1.0);
    return test::renderGpuAndCpu(context, scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
}

// Each device's mean of channel `c` within `tolerance` (relative) of `expected`, the closed form `formula`,
// printed with the per-pixel noise; the statistics, GPU then CPU.
std::array<PixelStatistics, 2> expectMeans(const test::RenderPair& pair, int c, double expected,
                                           double tolerance, const char* formula) {
    std::array<PixelStatistics, 2> statistics{statisticsOf(pair.gpu.image, c),
                                              statisticsOf(pair.cpu.image, c)};
    for (int i = 0; i < 2; ++i) {
        const char* device = i == 0 ? "gpu" : "cpu";
        std::printf("%s: mean %.5f (%s = %.5f), per-pixel noise %.2f%%\n", device, statistics[i].mean,
                    formula, expected, 100.0 * statistics[i].relativeDeviation);
        EXPECT_NEAR(statistics[i].mean, expected, tolerance * expected) << device;
    }
    return statistics;
}

TEST_F(Gpu, PlaneUnderAPolarCapShowsRLSinSquaredT) {
    // The top row of 32 is a cap of half-angle t = 180 / 32 = 5.625 degrees about +Y.
    const double radiance = 50.0, albedo = 0.5, t = M_PI / 32.0;
    const test::RenderPair pair = renderPlaneUnder(
        context(), mapOf(64, 32, [&](int, int y) { return glm::vec3(y == 0 ? float(radiance) : 0.0f); }),
        albedo, darkSettings(16, 16));
    for (const PixelStatistics& s :
         expectMeans(pair, 0, albedo * radiance * std::sin(t) * std::sin(t), 0.03, "r L sin^2 t")) {
        EXPECT_LT(s.relativeDeviation, 0.10) << "importance sampling finds the cap";
    }
}

TEST_F(Gpu, PlaneBesideASunFarBrighterThanItsSkySeesTheSky) {
    // An upward plane under a sky of radiance 1 over the upper half of the map, beside a texel below the
    // horizon 1e12 times as bright (the whole sky weighs 1e-9 of it): the plane shows r L, its albedo.
    // Whitted reaches the sky only by light samples. Drawn by luminance alone the sky was never sampled (its
    // rows had probability 0 in float on the GPU, and less than one random number's step on the CPU), and
    // both images were black.
    const double albedo = 0.5;
    const test::RenderPair pair =
        renderPlaneUnder(context(),
                         mapOf(64, 32,
                               [](int x, int y) {
                                   return glm::vec3(y < 16 ? 1.0f : x == 40 && y == 24 ? 1e12f : 0.0f);
                               }),
                         albedo, darkSettings(32, 256));
    // A twentieth of the samples reach the sky (the spread's half): per-pixel noise 4.6% at 256 samples.
    expectMeans(pair, 1, albedo, 0.06, "r L");
}

TEST_F(Gpu, TiltedPlaneMatchesBruteForceIrradianceOfATurnedMap) {
    // A dim sky with one bright patch, turned by 70 degrees; the plane tilts towards +X and +Z.
    Scene scene;
    const double albedo = 0.7;
    scene.materials.push_back(test::lambertian(static_cast<float>(albedo)));
    const glm::dvec3 normal = glm::normalize(glm::dvec3(0.6, 1.0, 0.3));
    addPlane(scene, normal, 1000.0, 0);
    scene.environment = mapOf(
        32, 16,
        [](int x, int y) {
            return x >= 20 && x <= 22 && y >= 4 && y <= 5 ? glm::vec3(30, 20, 10) : glm::vec3(0.2f);
        },
        70.0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    // The irradiance by brute force: the midpoint rule over the sphere, 32 x 32 cells per texel, through the
    // same nearest lookup.
    const EnvironmentTables tables(scene.environment);
    const glm::dvec3 irradiance = test::integrateOverSphere(16 * 32, 32 * 32, [&](const glm::dvec3& d) {
        return shading::environmentRadiance(tables, d) * std::max(0.0, glm::dot(d, normal));
    });
    const glm::dvec3 expected = albedo / M_PI * irradiance;
    const Camera camera = orthographic(5.0 * normal, -normal, {0, 1, 0}, 1.0);
    const test::RenderPair pair =
        test::renderGpuAndCpu(context(), scene, bvh, camera, darkSettings(16, 64), test::shaderCacheDir());
    for (const Image* image : {&pair.gpu.image, &pair.cpu.image}) {
        const char* device = image == &pair.gpu.image ? "gpu" : "cpu";
        std::printf("%s: red %.5f against %.5f by brute force\n", device, statisticsOf(*image, 0).mean,
                    expected.x);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(statisticsOf(*image, c).mean, expected[c], 0.03 * expected[c])
                << device << " channel " << c;
        }
    }
}

TEST_F(Gpu, MultipleImportanceSamplingKeepsTheMeanUnderAnEnvironment) {
    // Glossy gold spheres under a map with a bright patch: light samples alone (--no-mis) and light samples
    // weighed against traced lobe rays must agree; a wrong weight on either side double counts or loses light
    // (with weight 1 on escaped lobe rays the two differ by a quarter). The lobes are rough enough (0.35,
    // 0.6) for light samples alone to converge at 256 spp (at roughness 0.15 they still fall 2% short).
    Scene scene;
    for (float roughness : {0.35f, 0.6f}) {
        Material gold;
        gold.baseColor = glm::vec4(1.0f, 0.8f, 0.4f, 1.0f);
        gold.metallic = 1.0f;
        gold.roughness = roughness;
        scene.materials.push_back(gold);
        scene.spheres.push_back({glm::vec3(roughness < 0.5f ? -1.1f : 1.1f, 0.0f, 0.0f), 1.0f,
                                 static_cast<uint32_t>(scene.materials.size() - 1)});
    }
    scene.environment = mapOf(
        32, 16,
        [](int x, int y) {
            return x >= 12 && x <= 14 && y >= 3 && y <= 5 ? glm::vec3(40.0f) : glm::vec3(0.3f);
        },
        20.0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const Camera camera = orthographic({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 2.2);
    RenderSettings settings = darkSettings(32, 256);
    settings.lightSamples = 2;
    const test::RenderPair mis =
        test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    settings.multipleImportanceSampling = false;
    const test::RenderPair lightsOnly =
        test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    const double reference = statisticsOf(lightsOnly.cpu.image, 0).mean;
    std::printf("light samples alone %.5f, with MIS: cpu %.5f, gpu %.5f\n", reference,
                statisticsOf(mis.cpu.image, 0).mean, statisticsOf(mis.gpu.image, 0).mean);
    EXPECT_NEAR(statisticsOf(mis.cpu.image, 0).mean, reference, 0.02 * reference) << "cpu";
    EXPECT_NEAR(statisticsOf(mis.gpu.image, 0).mean, reference, 0.02 * reference) << "gpu";
    EXPECT_NEAR(statisticsOf(lightsOnly.gpu.image, 0).mean, reference, 0.02 * reference) << "gpu, no MIS";
}

TEST_F(Gpu, EnvironmentSceneMatchesTheReference) {
    auto [scene, bvh, camera] = ownScene("environment.gltf", 1.6);
    const Image sky = readRadianceImage((test::sourceDir() / "scenes/sky.hdr").string());
    scene.environment = makeEnvironmentMap("sky.hdr", sky.width, sky.height, sky.pixels, 40.0, 1.5);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 40;
    settings.samplesPerPixel = 4;
    settings.ambient = glm::dvec3(0.0);
    const Image gpu = renderGpu(scene, bvh, camera, settings).image;
    const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
    test::expectMatchesReference(gpu, cpu, "environment");
}

// Light adds: a scene lit by a point light, an area light and the environment at once renders, pixel for
// pixel, as the sum of the three renders lit by each alone (the same geometry, the lamp dark where it is not
// a light), on both devices and with both integrators. Each light sample draws its own random numbers
// whatever other lights there are, and paths and Whitted's ray trees do not depend on what the lights bring,
// so the sums agree to rounding: this checks that light sampling treats every kind alike when they meet (they
// share one loop and one shadow walk, shade_hit.h's directLight).
TEST_F(Gpu, LightsOfEveryKindAddUp) {
    enum Lights { kPoint = 1, kArea = 2, kEnvironment = 4 };
    auto sceneWith = [](int lights) {
        Scene scene;
        scene.materials.push_back(test::lambertian(0.7f));
        Material lamp = test::lambertian(0.0f);
        lamp.emission = glm::vec3((lights & kArea) != 0 ? 40.0f : 0.0f);
        lamp.doubleSided = true;
        scene.materials.push_back(lamp);
        addPlane(scene, {0, 1, 0}, 3.0, 0);
        scene.spheres.push_back({glm::vec3(0.3f, 0.5f, -0.2f), 0.5f, 0});
        // A lamp above the ground to one side, tilted towards the sphere; seen edge-on from above it hides
        // little.
        addFlatQuad(scene, {-1.6f, 1.2f, -0.3f}, {-1.6f, 1.2f, 0.3f}, {-1.2f, 1.6f, 0.3f},
                    {-1.2f, 1.6f, -0.3f}, 1);
        if ((lights & kPoint) != 0) {
            PunctualLight point;
            point.position = glm::dvec3(1.5, 2.5, 1.0);
            point.intensity = 40.0f;
            scene.lights.push_back(point);
        }
        if ((lights & kEnvironment) != 0) {
            scene.environment = mapOf(
                16, 8,
                [](int x, int y) { return x >= 3 && x <= 5 && y <= 2 ? glm::vec3(3.0f) : glm::vec3(0.1f); },
                30.0);
        }
        finalizeScene(scene);
        return scene;
    };
    const Camera camera = orthographic({0, 5, 0}, {0, -1, 0}, {0, 0, -1}, 2.0);
    const int size = 24;
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        RenderSettings settings = darkSettings(size, 4);
        settings.background = glm::dvec3(0.0);
        settings.integrator = integrator;
        settings.lightSamples = 2;
        std::vector<test::RenderPair> renders;
        for (int lights : {kPoint | kArea | kEnvironment, int(kPoint), int(kArea), int(kEnvironment)}) {
            const Scene scene = sceneWith(lights);
            renders.push_back(test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings,
                                                    test::shaderCacheDir()));
        }
        for (const bool gpu : {true, false}) {
            auto image = [&](size_t i) -> const Image& {
                return gpu ? renders[i].gpu.image : renders[i].cpu.image;
            };
            const std::string what = std::string(gpu ? "gpu " : "cpu ") + integratorName(integrator);
            double total = 0.0, worst = 0.0;
            double part[3] = {0.0, 0.0, 0.0};
            for (size_t p = 0; p < image(0).pixels.size(); ++p) {
                for (int c = 0; c < 3; ++c) {
                    const double all = image(0).pixels[p][c];
                    const double sum =
                        double(image(1).pixels[p][c]) + image(2).pixels[p][c] + image(3).pixels[p][c];
                    worst = std::max(worst, std::abs(all - sum) / (1e-3 + sum));
                    total += all;
                    for (int k = 0; k < 3; ++k) part[k] += image(k + 1).pixels[p][c];
                }
            }
            std::printf(
                "%s: all lights %.4f, point %.4f, area %.4f, environment %.4f; worst |all - sum| / sum "
                "%.2e\n",
                what.c_str(), total, part[0], part[1], part[2], worst);
            // Each kind lights a real share of the image, so one dropped or misweighed would show.
            for (int k = 0; k < 3; ++k) EXPECT_GT(part[k], 0.15 * total) << what << ": light kind " << k;
            EXPECT_LT(worst, gpu ? 1e-4 : 1e-6) << what;  // images hold floats
        }
    }
}

TEST_F(Gpu, OnlyScenesWithAnEnvironmentGetItsCodeAndBuffers) {
    auto [scene, bvh, camera] = ownScene("environment.gltf", 1.6);
    const GpuSceneData without = packScene(scene, bvh);
    EXPECT_FALSE(without.features.environment);
    EXPECT_TRUE(without.environmentTexels.empty() && without.environmentRows.empty());
    EXPECT_EQ(makeSceneParams(without, camera, scene.bounds, RenderSettings{}).environmentWidth, 0u);
    scene.environment = mapOf(8, 4, [](int x, int) { return glm::vec3(float(x)); });
    const GpuSceneData with = packScene(scene, bvh);
    EXPECT_TRUE(with.features.environment);
    EXPECT_EQ(with.environmentTexels.size(), 32u);
    EXPECT_EQ(with.environmentRows.size(), 4u);
    EXPECT_EQ(with.environmentRows.back(), 1.0f);
    const std::vector<std::string> defines = with.features.defines();
    EXPECT_NE(std::find(defines.begin(), defines.end(), "VKRT_HAS_ENVIRONMENT"), defines.end());
}

}  // namespace
}  // namespace vkrt
