// GPU images against the CPU reference with the same seed, under the validation layer: every scene in
// scenes/ and several third-party ones with the path integrator (the default), the own scenes with Whitted's
// too, and the variants of light sampling (without multiple importance sampling, several light samples with a
// Gaussian pixel filter).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "app/render_policy.h"
#include "scene/gltf_loader.h"
#include "scene/scene_builder.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::expectMatchesReference;
using test::Gpu;

struct SceneCase {
    std::string path;
    int width, height, spp;
    Integrator integrator = Integrator::Path;
};

void PrintTo(const SceneCase& c, std::ostream* out) {
    *out << std::filesystem::path(c.path).filename().string() << " " << c.width << "x" << c.height << " "
         << c.spp << " spp, " << integratorName(c.integrator);
}

class GpuImage : public Gpu, public ::testing::WithParamInterface<SceneCase> {};

// Renders the scene in `path` as the command would (its settings, camera and lighting, the neutral
// environment of scenes without lights included) on the GPU and by the CPU reference with the same seed.
test::RenderPair renderAsTheCommandWould(const VulkanContext& context, const std::string& path, int width,
                                         int height, int spp, Integrator integrator) {
    Scene scene = loadGltf(path);
    const FlatBvh bvh = bvhFor(scene);
    RenderRequest request;
    request.settings.width = width;
    request.height = height;
    request.settings.samplesPerPixel = spp;
    request.settings.seed = 7;
    request.settings.background = glm::dvec3(0.2, 0.3, 0.4);
    request.integrator = integrator;
    addNeutralEnvironment(request, scene);
    const RenderSetup setup = resolveRender(request, scene);
    return test::renderGpuAndCpu(context, scene, bvh, setup.camera, setup.settings, test::shaderCacheDir());
}

// The same image (test::expectMatchesReference) and the same rays as `reference`.
void expectSameRender(const RenderResult& result, const RenderResult& reference, const std::string& name) {
    expectMatchesReference(result.image, reference.image, name);
    EXPECT_EQ(result.rays.primary, reference.rays.primary) << name;
    EXPECT_NEAR(static_cast<double>(result.rays.shadow), static_cast<double>(reference.rays.shadow),
                0.002 * reference.rays.shadow + 2)
        << name;
    EXPECT_NEAR(static_cast<double>(result.rays.secondary), static_cast<double>(reference.rays.secondary),
                0.002 * reference.rays.secondary + 2)
        << name;
    EXPECT_EQ(result.rays.nonFiniteSamples, 0u) << name;
}

// The scene in `path` rendered as the command would, on the GPU as by the CPU reference.
void expectGpuMatchesCpu(const VulkanContext& context, const std::string& path, int width, int height,
                         int spp, Integrator integrator) {
    const auto [gpu, cpu] = renderAsTheCommandWould(context, path, width, height, spp, integrator);
    expectSameRender(gpu, cpu,
                     std::filesystem::path(path).stem().string() + "-" + integratorName(integrator));
}

TEST_P(GpuImage, MatchesCpuReference) {
    const SceneCase& c = GetParam();
    if (c.path.find("scenes-real") != std::string::npos && !test::haveScenesReal())
        GTEST_SKIP() << c.path << " is missing: ../shared/scenes-real is not beside the checkout";
    expectGpuMatchesCpu(context(), c.path, c.width, c.height, c.spp, c.integrator);
}

std::string own(const char* name) {
    return (test::sourceDir() / "scenes" / name).string();
}
std::string real(const char* name) {
    return (test::scenesReal() / name).string();
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GpuImage,
    ::testing::Values(
        SceneCase{own("cornell.gltf"), 64, 64, 4}, SceneCase{own("whitted.gltf"), 80, 60, 4},
        SceneCase{own("lights.gltf"), 80, 60, 4}, SceneCase{own("many-lights.gltf"), 80, 60, 4},
        SceneCase{own("dof.gltf"), 64, 48, 4}, SceneCase{own("glossy.gltf"), 80, 50, 4},
        SceneCase{own("motion-blur.gltf"), 80, 60, 4}, SceneCase{own("textures.gltf"), 80, 50, 4},
        SceneCase{own("surfaces.gltf"), 80, 50, 4}, SceneCase{own("environment.gltf"), 80, 50, 4},
        SceneCase{own("csg.gltf"), 80, 50, 4}, SceneCase{own("outdoor.gltf"), 64, 64, 4},
        SceneCase{own("deform.gltf"), 72, 48, 4}, SceneCase{own("cornell-meshopt.glb"), 64, 64, 4},
        SceneCase{own("cornell-draco.glb"), 64, 64, 4}, SceneCase{own("textures-webp.glb"), 80, 50, 4},
        SceneCase{own("cornell.gltf"), 64, 64, 4, Integrator::Whitted},
        SceneCase{own("whitted.gltf"), 80, 60, 4, Integrator::Whitted},
        SceneCase{own("lights.gltf"), 80, 60, 4, Integrator::Whitted},
        SceneCase{own("many-lights.gltf"), 80, 60, 4, Integrator::Whitted},
        SceneCase{own("dof.gltf"), 64, 48, 4, Integrator::Whitted},
        SceneCase{own("glossy.gltf"), 80, 50, 4, Integrator::Whitted},
        SceneCase{own("motion-blur.gltf"), 80, 60, 4, Integrator::Whitted},
        SceneCase{own("textures.gltf"), 80, 50, 4, Integrator::Whitted},
        SceneCase{own("surfaces.gltf"), 80, 50, 4, Integrator::Whitted},
        SceneCase{own("csg.gltf"), 80, 50, 4, Integrator::Whitted},
        SceneCase{own("outdoor.gltf"), 64, 64, 4, Integrator::Whitted},
        SceneCase{real("khronos-NormalTangentTest/glTF/NormalTangentTest.gltf"), 48, 48, 2},
        SceneCase{real("khronos-Duck/glTF-Binary/Duck.glb"), 48, 48, 2},
        SceneCase{real("khronos-AttenuationTest/AttenuationTest.glb"), 64, 48, 2},
        SceneCase{real("khronos-DamagedHelmet/glTF-Binary/DamagedHelmet.glb"), 48, 48, 2},
        SceneCase{real("playcanvas-lights/Lights.glb"), 48, 48, 2},
        SceneCase{real("cornell-box-nvidia/cornellBox.gltf"), 48, 48, 2},
        SceneCase{real("cornell-box-bevy/CornellBox.glb"), 48, 48, 2},
        SceneCase{real("glass-table-sketchfab/glass-table.glb"), 40, 40, 2},
        SceneCase{real("khronos-SimpleInstancing/SimpleInstancing.glb"), 40, 40, 2},
        SceneCase{real("khronos-TransmissionRoughnessTest/TransmissionRoughnessTest.glb"), 48, 32, 2},
        SceneCase{real("khronos-Suzanne/glTF/Suzanne.gltf"), 40, 40, 2},
        SceneCase{real("khronos-Cameras/glTF/Cameras.gltf"), 40, 40, 2},
        SceneCase{real("khronos-BoxTextured/glTF-Binary/BoxTextured.glb"), 40, 40, 2},
        SceneCase{real("playcanvas-lights/geometry-camera-light.glb"), 40, 40, 2},
        SceneCase{real("khronos-Avocado/glTF/Avocado.gltf"), 48, 48, 2},
        SceneCase{real("khronos-TextureTransformTest/glTF/TextureTransformTest.gltf"), 48, 48, 2}),
    [](const ::testing::TestParamInfo<SceneCase>& info) {
        std::string name = std::filesystem::path(info.param.path).stem().string() +
                           (info.param.integrator == Integrator::Whitted ? "Whitted" : "");
        name.erase(std::remove_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(ch); }),
                   name.end());
        return name;
    });

// Scenes drawn at random (tools/random_scenes.py: meshes, spheres, shapes and CSG objects of every material
// kind, textures with holes and transforms, normal maps, vertex colours, mirrored, morphed and skinned
// meshes, punctual lights, perspective and orthographic cameras, now and then a lens or motion), one seed
// each, paths for odd seeds and Whitted for even ones, 48 x 48 pixels at 4 samples. The first 60 seeds found
// the devices tracing different shadow rays (by up to a third) where a lamp and the point it lights lie in
// one plane (shade_hit.h's areaLightQuery); since, all 60 match. Seeds 1 to 80 with either integrator, and 81
// to 150 with an environment map, several light samples, a tent or Gaussian filter, no multiple importance
// sampling or every shader feature, differed in at most 8 of 2,304 pixels by more than 1% (through the
// command line, 2026-12-07). With the generator's later features (the textures' transforms and second
// coordinates onwards), seeds 1 to 100 differed in at most 2 pixels; seed 91 traced 2% more rays on the GPU,
// all past the sixth bounce inside a normal-mapped glass cylinder of index 2.35 (the same rays at --max-depth
// 6; README, Testing: bumpy glass parts the devices' samples).
class GpuRandomScene : public Gpu, public ::testing::WithParamInterface<int> {};

// tools/random_scenes.py's scene of `seed` in the test's temporary folder, as `name`, with the generator's
// `options`.
std::string randomScene(int seed, const std::string& name, const std::string& options = "") {
    const std::filesystem::path file = test::temporaryFolder() / (name + ".gltf");
    const std::string command = std::string(VKRT_PYTHON) + " " +
                                (test::sourceDir() / "tools" / "random_scenes.py").string() + " " +
                                std::to_string(seed) + " " + file.string() + " " + options;
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return file.string();
}

Integrator integratorOfSeed(int seed) {
    return seed % 2 == 1 ? Integrator::Path : Integrator::Whitted;
}

TEST_P(GpuRandomScene, MatchesCpuReference) {
    const int seed = GetParam();
    expectGpuMatchesCpu(context(), randomScene(seed, "random-" + std::to_string(seed)), 48, 48, 4,
                        integratorOfSeed(seed));
}

INSTANTIATE_TEST_SUITE_P(Seeds, GpuRandomScene, ::testing::Range(1, 17));

// Numerical stability: a random scene scaled by 1e-4 and by 1e4 (its lens, media and point lights'
// intensities with it: tools/random_scenes.py --scale), and scaled by 1e4 and moved 1e6 away, shows on both
// devices the image the CPU reference shows of it as it is. Seeds 1 to 40, paths and Whitted alternately,
// also scaled by 1e-3 and 1e3 and moved 1e5 away, differed from that image by more than 1% in at most 2 of
// 2,304 pixels on either device (2026-12-07); seeds 6, 15 and 35 here are three of the five with 2. With the
// generator's later features, seeds 13 (skinned, morphed and twice-shown meshes), 24 (a skinned mesh, an
// orthographic camera) and 43 (a morph, an orthographic camera) differed in none; of 13 seeds tried so, seed
// 79 differed in up to 10 pixels, on the CPU as on the GPU, all inside a CSG solid of rough glass (roughness
// 0.7: every internal bounce a rejection loop, which rounding steers; with the glass smooth, in none).
class GpuRandomSceneScaled : public Gpu, public ::testing::WithParamInterface<int> {};

TEST_P(GpuRandomSceneScaled, ShowsTheImageOfTheSceneAsItIs) {
    const int seed = GetParam();
    const std::string name = "random-" + std::to_string(seed);
    const Integrator integrator = integratorOfSeed(seed);
    const RenderResult reference =
        renderAsTheCommandWould(context(), randomScene(seed, name), 48, 48, 4, integrator).cpu;
    for (const auto& [tag, options] : {std::pair<std::string, std::string>{"small", "--scale 1e-4"},
                                       {"large", "--scale 1e4"},
                                       {"large-and-far", "--scale 1e4 --offset 1000000 0 1000000"}}) {
        const auto [gpu, cpu] = renderAsTheCommandWould(
            context(), randomScene(seed, name + "-" + tag, options), 48, 48, 4, integrator);
        expectSameRender(cpu, reference, name + "-" + tag + "-cpu");
        expectSameRender(gpu, reference, name + "-" + tag + "-gpu");
    }
}

INSTANTIATE_TEST_SUITE_P(Seeds, GpuRandomSceneScaled, ::testing::Values(6, 13, 15, 24, 35, 43));

TEST_F(Gpu, GlossyLobesWithoutMultipleImportanceSamplingMatchCpuReference) {
    const auto [scene, bvh, camera] = ownScene("glossy.gltf", 1.6);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 40;
    settings.samplesPerPixel = 4;
    settings.lightSamples = 3;
    settings.multipleImportanceSampling = false;
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    expectMatchesReference(gpu.image, cpu.image, "glossy-no-mis");
}

TEST_F(Gpu, SeveralLightSamplesAndAGaussianFilterMatchCpuReference) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 48;
    settings.samplesPerPixel = 2;
    settings.lightSamples = 6;
    settings.pixelFilter = PixelFilter::Gaussian;
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
    expectMatchesReference(gpu.image, cpu.image, "cornell-6-light-samples");
    EXPECT_NEAR(static_cast<double>(gpu.rays.shadow), static_cast<double>(cpu.rays.shadow),
                0.002 * cpu.rays.shadow);
}

// A lens focused farther than 1.8e19 aimed its rays through a vector whose squared length overflowed single
// precision: the GPU drew background alone where the CPU drew the focus-at-infinity blur. Up to float's
// largest value the GPU draws what the CPU draws, and what a far finite focus (1e15) draws.
TEST_F(Gpu, LensFocusedAt1e30Or3e38BlursLikeTheCpuAndLikeAFocusAt1e15) {
    auto [scene, bvh, camera] = ownScene("dof.gltf", 64.0 / 48.0);
    ASSERT_GT(camera.aperture, 0.0);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 4;
    settings.seed = 7;
    camera.focusDistance = 1e15;
    const RenderResult farFinite = renderGpu(scene, bvh, camera, settings);
    for (double focus : {1e30, 3.4e38}) {
        camera.focusDistance = focus;
        const auto [gpu, cpu] =
            test::renderGpuAndCpu(context(), scene, bvh, camera, settings, test::shaderCacheDir());
        const std::string name = "dof-focus-" + std::to_string(static_cast<int>(std::log10(focus)));
        expectMatchesReference(gpu.image, cpu.image, name);
        expectMatchesReference(gpu.image, farFinite.image, name + "-against-1e15");
        EXPECT_EQ(gpu.rays.nonFiniteSamples, 0u) << name;
    }
}

// A lens a thousand times wider than its focus distance: a ray from its rim, its origin and aim rounded to
// float out there, landed epsilon times the lens radius off. It now starts where it comes within the scene's
// radius of the pinhole (shaders/camera.h). A checker of Lambertian quads (index 1) in the plane of focus,
// which every lens ray meets where the pinhole's ray does, lit by Whitted's ambient term alone: the lens
// image is the pinhole's but for the samples that single precision still misplaces, those meeting the plane
// at grazing angles (an error of about epsilon over the angle, which no origin removes). 256 x 256, 4 spp, on
// lavapipe: the mean difference 0.000188, and 0.000405 with rays from the rim (about 80 and 180 samples
// across an edge of the checker).
TEST_F(Gpu, LensFarWiderThanItsFocusStartsItsRaysNearTheScene) {
    Scene scene;
    for (const float albedo : {0.8f, 0.2f}) {
        Material m;
        m.baseColor = glm::vec4(glm::vec3(albedo), 1.0f);
        m.metallic = 0.0f;
        m.roughness = 1.0f;
        m.ior = 1.0f;  // no specular reflection: the same radiance from every direction
        scene.materials.push_back(m);
    }
    constexpr int kSquares = 8;
    constexpr float kFocus = 5.0f, kHalf = 2.0f, kSide = 2.0f * kHalf / kSquares;
    for (int i = 0; i < kSquares; ++i) {
        for (int j = 0; j < kSquares; ++j) {
            const float x = -kHalf + kSide * i, y = -kHalf + kSide * j;
            addFlatQuad(scene, {x, y, 0.0f}, {x + kSide, y, 0.0f}, {x + kSide, y + kSide, 0.0f},
                        {x, y + kSide, 0.0f}, static_cast<uint32_t>((i + j) % 2));
        }
    }
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera;
    camera.position = glm::dvec3(0.0, 0.0, kFocus);
    camera.yfov = 0.6;
    RenderSettings settings;
    settings.integrator = Integrator::Whitted;
    settings.ambient = glm::dvec3(1.0);
    settings.width = settings.height = 256;
    settings.samplesPerPixel = 4;
    const RenderResult pinhole = renderGpu(scene, bvh, camera, settings);
    camera.aperture = 1000.0 * kFocus;
    camera.focusDistance = kFocus;
    const RenderResult lens = renderGpu(scene, bvh, camera, settings);
    double difference = 0.0;
    for (size_t i = 0; i < pinhole.image.pixels.size(); ++i)
        difference +=
            glm::length(glm::dvec3(lens.image.pixels[i] - pinhole.image.pixels[i])) / std::sqrt(3.0);
    difference /= static_cast<double>(pinhole.image.pixels.size());
    EXPECT_LT(difference, 0.00028);
    EXPECT_GT(pinhole.image.pixels[0].x, 0.1f) << "the checker fills the view";
}

}  // namespace
}  // namespace vkrt
