// The GPU tracer on lavapipe (or whatever Vulkan device is present), always under the Khronos validation
// layer: images against the CPU reference, rays against CPU traversal, random numbers bit for bit, shader
// variants, dispatch chunking, time limits and a scene too large for one storage-buffer descriptor.
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include <gtest/gtest.h>

#include "bvh/triangle_bvh.h"
#include "cpu/closest_hit.h"
#include "cpu/reference_renderer.h"
#include "cpu/triangle_intersection.h"
#include "gpu/compute_pipeline.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/gpu_renderer.h"
#include "gpu/gpu_timer.h"
#include "gpu/shader_compiler.h"
#include "gpu/vulkan_context.h"
#include "image/image_metrics.h"
#include "random.h"
#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "test_support.h"

namespace vkrt {
namespace {

const std::string kShaderCache = (std::filesystem::temp_directory_path() / "vkrt-test-shader-cache").string();

// One validated Vulkan context for the whole test program; every test must leave it without messages.
class Gpu : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        if (!context_) {
            ContextOptions options;
            options.validation = true;
            context_ = std::make_unique<VulkanContext>(options);
        }
    }
    void SetUp() override { messagesBefore_ = context_->validationMessages(); }
    void TearDown() override {
        EXPECT_EQ(context_->validationMessages(), messagesBefore_)
            << "the validation layer reported problems";
    }
    static const VulkanContext& context() { return *context_; }

    static FlatBvh bvhFor(const Scene& scene) { return buildSceneBvh(scene).flat; }

    // One of the project's own scenes (scenes/NAME), its BVH and its first camera for an aspect ratio.
    struct SceneUnderTest {
        Scene scene;
        FlatBvh bvh;
        Camera camera;
    };
    static SceneUnderTest ownScene(const char* name, double aspect) {
        Scene scene = loadGltf((test::sourceDir() / "scenes" / name).string());
        FlatBvh bvh = bvhFor(scene);
        const Camera camera = selectCamera(scene, 0, aspect);
        return {std::move(scene), std::move(bvh), camera};
    }

    static RenderResult renderGpu(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                                  const RenderSettings& settings, GpuRenderOptions options = {},
                                  GpuRenderReport* report = nullptr) {
        options.shaderCacheDir = kShaderCache;
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        RenderResult result = renderer.render();
        if (report) *report = renderer.report();
        return result;
    }

  private:
    static inline std::unique_ptr<VulkanContext> context_;
    uint32_t messagesBefore_ = 0;
};

// GPU against the CPU reference with the same seed: at least 99.5% of pixels within 1% (with a small
// absolute floor for dark pixels) and a mean relative error of at most 0.2%.
void expectMatchesReference(const Image& gpu, const Image& cpu, const std::string& name) {
    const ImageDifference d = compareImages(gpu, cpu, 0.01, 2e-3);
    EXPECT_LE(d.fractionOff, 0.005) << name << ": " << d.fractionOff * 100 << "% of pixels off";
    EXPECT_LE(d.meanRelativeError, 0.002) << name;
    if (d.fractionOff > 0.005 || d.meanRelativeError > 0.002) test::saveForInspection(gpu, cpu, name);
}

struct SceneCase {
    std::string path;
    int width, height, spp;
};

void PrintTo(const SceneCase& c, std::ostream* out) {
    *out << std::filesystem::path(c.path).filename().string() << " " << c.width << "x" << c.height << " "
         << c.spp << " spp";
}

class GpuImage : public Gpu, public ::testing::WithParamInterface<SceneCase> {};

TEST_P(GpuImage, MatchesCpuReference) {
    const SceneCase& c = GetParam();
    if (c.path.find("scenes-real") != std::string::npos && !test::haveScenesReal()) GTEST_SKIP();
    const Scene scene = loadGltf(c.path);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings;
    settings.width = c.width;
    settings.height = c.height;
    settings.samplesPerPixel = c.spp;
    settings.seed = 7;
    const bool hasLights =
        !scene.lights.empty() || !scene.emissiveTriangles.empty() || !scene.emissiveSpheres.empty();
    settings.ambient = glm::dvec3(hasLights ? 0.05 : 1.0);
    settings.background = glm::dvec3(0.2, 0.3, 0.4);
    const Camera camera = selectCamera(scene, 0, static_cast<double>(c.width) / c.height);
    const RenderResult gpu = renderGpu(scene, bvh, camera, settings);
    const RenderResult cpu = ReferenceRenderer(scene, bvh, camera, settings).render();
    expectMatchesReference(gpu.image, cpu.image, std::filesystem::path(c.path).stem().string());
    EXPECT_EQ(gpu.rays.primary, cpu.rays.primary);
    EXPECT_NEAR(static_cast<double>(gpu.rays.shadow), static_cast<double>(cpu.rays.shadow),
                0.002 * cpu.rays.shadow + 2);
    EXPECT_NEAR(static_cast<double>(gpu.rays.secondary), static_cast<double>(cpu.rays.secondary),
                0.002 * cpu.rays.secondary + 2);
    EXPECT_EQ(gpu.rays.nonFiniteSamples, 0u);
}

std::string own(const char* name) {
    return (test::sourceDir() / "scenes" / name).string();
}
std::string real(const char* name) {
    return (test::scenesReal() / name).string();
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuImage,
    ::testing::Values(SceneCase{own("cornell.gltf"), 64, 64, 4}, SceneCase{own("whitted.gltf"), 80, 60, 4},
                      SceneCase{own("lights.gltf"), 80, 60, 4}, SceneCase{own("dof.gltf"), 64, 48, 4},
                      SceneCase{own("glossy.gltf"), 80, 50, 4}, SceneCase{own("motion-blur.gltf"), 80, 60, 4},
                      SceneCase{real("khronos-Duck/glTF-Binary/Duck.glb"), 48, 48, 2},
                      SceneCase{real("khronos-AttenuationTest/AttenuationTest.glb"), 64, 48, 2},
                      SceneCase{real("khronos-DamagedHelmet/glTF-Binary/DamagedHelmet.glb"), 48, 48, 2},
                      SceneCase{real("playcanvas-lights/Lights.glb"), 48, 48, 2},
                      SceneCase{real("cornell-box-nvidia/cornellBox.gltf"), 48, 48, 2}),
    [](const ::testing::TestParamInfo<SceneCase>& info) {
        std::string name = std::filesystem::path(info.param.path).stem().string();
        name.erase(std::remove_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(ch); }),
                   name.end());
        return name;
    });

TEST_F(Gpu, GlossyLobesWithoutMultipleImportanceSamplingMatchCpuReference) {
    const auto [scene, bvh, camera] = ownScene("glossy.gltf", 1.6);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 40;
    settings.samplesPerPixel = 4;
    settings.lightSamples = 3;
    settings.multipleImportanceSampling = false;
    const RenderResult gpu = renderGpu(scene, bvh, camera, settings);
    const RenderResult cpu = ReferenceRenderer(scene, bvh, camera, settings).render();
    expectMatchesReference(gpu.image, cpu.image, "glossy-no-mis");
}

TEST_F(Gpu, SeveralLightSamplesAndAGaussianFilterMatchCpuReference) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 48;
    settings.samplesPerPixel = 2;
    settings.lightSamples = 6;
    settings.pixelFilter = PixelFilter::Gaussian;
    const RenderResult gpu = renderGpu(scene, bvh, camera, settings);
    const RenderResult cpu = ReferenceRenderer(scene, bvh, camera, settings).render();
    expectMatchesReference(gpu.image, cpu.image, "cornell-6-light-samples");
    EXPECT_NEAR(static_cast<double>(gpu.rays.shadow), static_cast<double>(cpu.rays.shadow),
                0.002 * cpu.rays.shadow);
}

TEST_F(Gpu, WhiteFurnaceNeverGainsEnergy) {
    // A metal sphere with F0 = 1 (white base colour, metallic 1) of roughness 0, 0.25, 0.5 or 1 in a uniform
    // white environment (background and ambient radiance 1, no lights). Energy never grows: every pixel is
    // at most 1; the mirror returns exactly 1; rough GGX loses what single scattering cannot return.
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
        RenderSettings settings;
        settings.width = settings.height = 24;
        settings.samplesPerPixel = 8;
        settings.ambient = glm::dvec3(1.0);
        settings.background = glm::dvec3(1.0);
        Camera camera;
        camera.projection = Projection::Orthographic;
        camera.position = {0.0, 0.0, 5.0};
        camera.xmag = camera.ymag = 1.0;  // the sphere fills the film's inscribed disk
        const Image gpu = renderGpu(scene, bvh, camera, settings).image;
        const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (const Image* image : {&gpu, &cpu}) {
            const std::string which =
                std::string(image == &gpu ? "gpu" : "cpu") + " roughness " + std::to_string(roughness);
            double sum = 0.0;
            for (const glm::vec3& p : image->pixels) {
                ASSERT_LE(std::max({p.x, p.y, p.z}), 1.0f + 1e-5f) << which;
                if (roughness == 0.0f) {
                    ASSERT_NEAR(p.x, 1.0f, 1e-5f) << which;
                }
                sum += p.x;
            }
            const double mean = sum / static_cast<double>(image->pixels.size());
            // Single-scattering GGX loses energy as roughness grows (about half at roughness 1, which
            // multiple-scattering compensation would return); the image must show that, not a constant.
            const double lowest = roughness <= 0.25f ? 0.95 : roughness <= 0.5f ? 0.85 : 0.45;
            EXPECT_GT(mean, lowest) << which;
            if (roughness == 1.0f) {
                EXPECT_LT(mean, 0.7) << which;
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

TEST_F(Gpu, RandomNumbersMatchTheCppDefinitionBitForBit) {
    std::ifstream file(test::sourceDir() / "tests/glsl/random_check.comp");
    std::stringstream source;
    source << file.rdbuf();
    const CompiledShader shader = compileShaderSource("random_check.comp", source.str(), {}, kShaderCache);
    ComputePipeline pipeline(context(), shader.spirv, 1, 16);
    constexpr uint32_t count = 100000, seed = 12345;
    GpuBuffer out(context(), count * 4 * sizeof(uint32_t));
    pipeline.bind({&out});
    const uint32_t constants[4] = {seed, count, 0, 0};
    context().submitAndWait([&](VkCommandBuffer commands) {
        pipeline.dispatch(commands, constants, sizeof(constants), (count + 63) / 64, 1);
        makeShaderWritesVisibleToHost(commands);
    });
    std::vector<uint32_t> words(count * 4);
    out.download(words.data(), words.size() * sizeof(uint32_t));
    auto bitsOf = [](float value) {
        uint32_t bits;
        std::memcpy(&bits, &value, 4);
        return bits;
    };
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t pixel = i * 7919u, sample = i % 1024u, dimension = i % 37u;
        ASSERT_EQ(words[4 * i], vkrtRandomBits(seed, pixel, sample, dimension)) << i;
        ASSERT_EQ(words[4 * i + 1], bitsOf(vkrtRandom(seed, pixel, sample, dimension))) << i;
        ASSERT_EQ(words[4 * i + 2], bitsOf(vkrtStratified(seed, pixel, sample, dimension, 0))) << i;
        ASSERT_EQ(words[4 * i + 3], bitsOf(vkrtStratified(seed, pixel, sample, dimension, 1))) << i;
    }
}

// Rays of three kinds against one mesh: camera-like (from a point outside, towards the mesh), shadow-like
// (between two points near the surface) and incoherent (random origins and directions).
std::vector<gpu::GpuRay> testRays(const Aabb& bounds, int count) {
    std::vector<gpu::GpuRay> rays;
    const glm::vec3 lo = bounds.min, extent = bounds.extent(), center = bounds.center();
    const float radius = glm::length(extent);
    for (int i = 0; i < count; ++i) {
        auto r = [&](uint32_t d) { return vkrtRandom(99, static_cast<uint32_t>(i), 0, d); };
        const glm::vec3 inside = lo + extent * glm::vec3(r(0), r(1), r(2));
        glm::vec3 origin, direction;
        switch (i % 3) {
            case 0:  // camera: from a fixed eye
                origin = center + glm::vec3(0.3f, 0.2f, 1.5f) * radius;
                break;
            case 1:  // shadow: from another point inside the box
                origin = lo + extent * glm::vec3(r(3), r(4), r(5));
                break;
            default:  // incoherent
                origin = center + radius * (glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f);
                break;
        }
        direction = glm::normalize(inside - origin);
        if (!std::isfinite(direction.x)) direction = glm::vec3(0, 0, 1);
        rays.push_back({origin, 0.0f, direction, i % 3 == 1 ? glm::length(inside - origin) : 1e30f});
    }
    return rays;
}

Scene sceneOf(const std::vector<Triangle>& triangles, const std::vector<Sphere>& spheres = {}) {
    Scene scene;
    scene.materials.push_back(Material{});
    for (const Triangle& t : triangles) addFlatTriangle(scene, t.v0, t.v1, t.v2, 0);
    scene.spheres = spheres;
    finalizeScene(scene);
    return scene;
}

void expectRaysMatchCpu(const VulkanContext& context, const Scene& scene, const char* name) {
    const FlatBvh bvh = buildSceneBvh(scene).flat;
    GpuRaycaster raycaster(context, scene, bvh, kShaderCache);
    const std::vector<gpu::GpuRay> rays = testRays(scene.bounds, 30000);
    const std::vector<gpu::GpuHit> closest = raycaster.trace(rays, RaycastMode::Closest);
    const std::vector<gpu::GpuHit> any = raycaster.trace(rays, RaycastMode::Any);
    const double sceneSize = glm::length(scene.bounds.extent());
    size_t samePrimitive = 0, ties = 0, hitMissDisagreements = 0, occlusionDisagreements = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        SurfaceHit cpu;
        closestHit(scene, bvh, ray, rays[i].tMax, kNoPrimitive, cpu);
        const uint32_t cpuTriangle = cpu.primitive;
        const double tMax = cpu.primitive == kNoPrimitive ? rays[i].tMax : cpu.t;
        const bool cpuHit = cpuTriangle != VKRT_NO_HIT, gpuHit = closest[i].primitive != VKRT_NO_HIT;
        hits += cpuHit;
        if (cpuHit != gpuHit) {
            ++hitMissDisagreements;
        } else if (cpuHit) {
            // Distances agree to 1e-5 relative, plus a floor of a few float ulps of the scene's size for hits
            // very close to the origin; a different triangle is allowed only at the same distance.
            ASSERT_NEAR(closest[i].t, tMax, 1e-5 * tMax + 1e-6 * sceneSize) << name << " ray " << i;
            if (closest[i].primitive == cpuTriangle)
                ++samePrimitive;
            else
                ++ties;
        }
        if ((any[i].primitive != VKRT_NO_HIT) != cpuHit) ++occlusionDisagreements;
    }
    ASSERT_GT(hits, rays.size() / 4) << name;
    const double agreeing = static_cast<double>(samePrimitive) / static_cast<double>(hits);
    EXPECT_GE(agreeing, 0.9999) << name << ": " << ties << " ties, " << hitMissDisagreements << " hit/miss";
    EXPECT_EQ(hitMissDisagreements, 0u) << name << ": every mismatch must be a tie";
    std::printf("%s: %zu rays, %zu hits, %zu ties, %zu hit/miss, %zu occlusion disagreements\n", name,
                rays.size(), hits, ties, hitMissDisagreements, occlusionDisagreements);
    EXPECT_LE(occlusionDisagreements, rays.size() / 10000) << name;
}

TEST_F(Gpu, RaysMatchCpuTraversalOnProceduralMeshes) {
    expectRaysMatchCpu(context(), sceneOf(makeUvSphere(glm::vec3(0.2f), 1.3f, 60, 120)), "sphere");
    expectRaysMatchCpu(context(), sceneOf(makeTriangleSoup(20000, 4, 0.1f)), "soup");
    // 20k identical triangles over a large quad, and a huge triangle below: stacks of ties and wide boxes.
    std::vector<Triangle> stack = makeTriangleSoup(2000, 8, 0.3f);
    stack.push_back({{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, 0});
    stack.insert(stack.end(), 20000, Triangle{{0.1f, 0.2f, 0.5f}, {0.9f, 0.2f, 0.5f}, {0.5f, 0.9f, 0.5f}, 0});
    stack.push_back({{-1e5f, -1.0f, -1e5f}, {1e5f, -1.0f, -1e5f}, {0.0f, -1.0f, 1e5f}, 0});
    expectRaysMatchCpu(context(), sceneOf(stack), "identical triangles and a huge one");
}

TEST_F(Gpu, RaysMatchCpuOnAnalyticSpheres) {
    // Spheres from 1e-3 to 1e3 in radius beside triangles, one far from the rest: the float test of
    // shaders/sphere.glsl against the double one, through the shared BVH.
    std::vector<Sphere> spheres;
    uint32_t state = 12345u;
    auto next = [&] { return static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
    for (int i = 0; i < 400; ++i) {
        const float radius = std::pow(10.0f, -2.0f + 2.5f * next());
        spheres.push_back({glm::vec3(next(), next(), next()) * 4.0f - 2.0f, radius, 0});
    }
    spheres.push_back({{0.0f, -1003.0f, 0.0f}, 1000.0f, 0});  // a huge sphere as the ground
    spheres.push_back({{0.5f, 0.5f, 0.5f}, 1e-3f, 0});
    expectRaysMatchCpu(context(), sceneOf(makeTriangleSoup(2000, 4, 0.1f), spheres), "spheres and triangles");
}

TEST_F(Gpu, RaysMatchCpuTraversalOnRealModels) {
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal();
    for (const char* model : {"khronos-Duck/glTF-Binary/Duck.glb", "khronos-Suzanne/glTF/Suzanne.gltf",
                              "cornell-box-nvidia/cornellBox.gltf"}) {
        expectRaysMatchCpu(context(), loadGltf((test::scenesReal() / model).string()), model);
    }
}

TEST_F(Gpu, UnusedFeaturesAreCompiledOutWithoutChangingTheImage) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 2;

    GpuRenderOptions options;
    options.shaderCacheDir = kShaderCache;
    GpuRenderer lean(context(), scene, bvh, camera, settings, options);
    options.allFeatures = true;
    GpuRenderer full(context(), scene, bvh, camera, settings, options);
    // The Cornell box has area lights only: no transmission, volumes, textures or punctual lights.
    EXPECT_EQ(lean.features().defines(), std::vector<std::string>{"VKRT_HAS_AREA_LIGHTS"});
    EXPECT_EQ(full.features().defines(), SceneFeatures::all().defines());
    EXPECT_EQ(full.features().defines().size(), 9u);
    for (const std::string& define : lean.defines()) {
        EXPECT_TRUE(define == "VKRT_HAS_AREA_LIGHTS" || define == "VKRT_BOUND_GEOMETRY") << define;
    }
    EXPECT_LT(lean.spirv().size(), full.spirv().size());
    // glslang keeps function names (OpName) in the SPIR-V: the lean module has none of the left-out code.
    auto names = [](const std::vector<uint32_t>& spirv, const std::string& name) {
        const std::string bytes(reinterpret_cast<const char*>(spirv.data()), spirv.size() * 4);
        return bytes.find(name) != std::string::npos;
    };
    for (const char* function :
         {"beerLambert", "refractThrough", "sampleTexture", "arriveFrom", "sphereRoots", "concentricDisk"}) {
        EXPECT_TRUE(names(full.spirv(), function)) << function;
        EXPECT_FALSE(names(lean.spirv(), function))
            << function << " is compiled in but the scene does not need it";
    }
    const Image a = lean.render().image, b = full.render().image;
    const ImageDifference d = compareImages(a, b, 1e-5, 1e-7);
    EXPECT_EQ(d.fractionOff, 0.0) << "leaving out unused paths must not change the image";
}

TEST_F(Gpu, BoundAndAddressedGeometryGiveTheSameImage) {
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 2;
    GpuRenderOptions addressed;
    addressed.deviceAddressesOnly = true;
    GpuRenderReport boundReport, addressedReport;
    const Image a = renderGpu(scene, bvh, camera, settings, {}, &boundReport).image;
    const Image b = renderGpu(scene, bvh, camera, settings, addressed, &addressedReport).image;
    EXPECT_TRUE(boundReport.boundGeometry);
    EXPECT_FALSE(addressedReport.boundGeometry);
    EXPECT_EQ(compareImages(a, b, 1e-6, 1e-8).fractionOff, 0.0);
}

TEST_F(Gpu, ChunkingDoesNotChangeTheImage) {
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 6;
    GpuRenderOptions tiny, huge;
    tiny.targetDispatchMs = 1e-6;  // one row, one sample per dispatch
    huge.targetDispatchMs = 1e9;
    GpuRenderReport tinyReport, hugeReport;
    const Image a = renderGpu(scene, bvh, camera, settings, tiny, &tinyReport).image;
    const Image b = renderGpu(scene, bvh, camera, settings, huge, &hugeReport).image;
    EXPECT_EQ(tinyReport.dispatches, 30u * 6u);  // one row, one sample at a time
    EXPECT_LT(hugeReport.dispatches, 10u);
    EXPECT_EQ(compareImages(a, b, 1e-5, 1e-7).fractionOff, 0.0);
}

TEST_F(Gpu, TimeLimitStopsAfterThePassThatCrossesIt) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 100000;
    GpuRenderOptions options;
    options.timeLimitSeconds = 1e-6;
    GpuRenderReport report;
    const RenderResult result = renderGpu(scene, bvh, camera, settings, options, &report);
    EXPECT_GE(report.samplesPerPixel, 1u);
    EXPECT_LT(report.samplesPerPixel, 100000u);
    EXPECT_EQ(result.rays.primary, 32u * 32u * report.samplesPerPixel);
    EXPECT_GT(result.image.at(16, 16).x, 0.0f);
}

TEST_F(Gpu, FiveMillionTrianglesRender) {
    // 5M triangles: 240 MB of triangles and 320 MB of nodes, beyond lavapipe's 128 MiB storage-buffer
    // range; buffer device addresses have no such limit.
    Scene scene;
    Material white;
    white.metallic = 0.0f;
    scene.materials.push_back(white);
    scene.triangles = makeUvSphere(glm::vec3(0.0f), 1.0f, 1582, 1582);
    ASSERT_GE(scene.triangles.size(), 5'000'000u);
    scene.shading.resize(scene.triangles.size());
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        const glm::vec3 n = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
        scene.shading[i].normal[0] = scene.shading[i].normal[1] = scene.shading[i].normal[2] = n;
    }
    PunctualLight light;
    light.position = {0.0, 0.0, 5.0};
    light.intensity = 25.0f;
    scene.lights.push_back(light);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings;
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 1;
    settings.ambient = glm::dvec3(0.0);
    GpuRenderReport report;
    const RenderResult result = renderGpu(scene, bvh, frameBounds(scene.bounds, 1.0), settings, {}, &report);
    EXPECT_GT(report.deviceMemoryBytes, 128ull << 20);
    EXPECT_FALSE(report.boundGeometry) << "too large for one storage-buffer descriptor on lavapipe";
    // The sphere faces the light head on: (rho + F0) / pi * I / d^2 with d = 4 (white, F0 = 0.04).
    const glm::vec3 centre = result.image.at(8, 8);
    EXPECT_NEAR(centre.x, 1.04 / M_PI * 25.0 / 16.0, 0.02);
}

}  // namespace
}  // namespace vkrt
