// The GPU renderer's own machinery, under the validation layer: shader variants without unused features,
// geometry bound as descriptors or reached by device address, dispatch chunking, the time limit, and a
// 5M-triangle scene too large for one storage-buffer descriptor.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/reference_renderer.h"
#include "gpu/device_memory_plan.h"
#include "gpu/dispatch_planner.h"
#include "gpu/gpu_buffer.h"
#include "gpu/gpu_renderer.h"
#include "gpu/gpu_scene.h"
#include "gpu/scene_features.h"
#include "gpu/shader_compiler.h"
#include "gpu/workgroup_order.h"
#include "image/image_metrics.h"
#include "scene/camera_selection.h"
#include "scene/environment_map.h"
#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "spread_workgroups.h"
#include "support/gpu_fixture.h"
#include "support/huge_pages.h"
#include "support/reference_comparison.h"
#include "support/render_both.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

// The Whitted scene at 40 x 30 pixels.
RenderSettings smallWhitted(int samplesPerPixel) {
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = samplesPerPixel;
    return settings;
}

// The Cornell box at 24 x 24 pixels, path traced.
RenderSettings smallCornellPaths(int samplesPerPixel) {
    RenderSettings settings;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = samplesPerPixel;
    settings.integrator = Integrator::Path;
    return settings;
}

// Where the device can keep IEEE 754's signed zeros, infinities and NaNs in single precision, the tracing kernel
// asks for them (shaders/ieee_floats.glsl): its SPIR-V declares the SignedZeroInfNanPreserve execution mode for
// 32-bit floats, with its capability; elsewhere it declares neither.
TEST_F(Gpu, KernelAsksForIeeeFloatsWhereTheDeviceKeepsThem) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    const GpuRenderer renderer(context(), scene, bvh, camera, smallWhitted(1), options);
    const std::vector<uint32_t>& spirv = renderer.spirv();
    constexpr uint32_t kOpCapability = 17, kOpExecutionMode = 16, kSignedZeroInfNanPreserve = 4461,
                       kSignedZeroInfNanPreserveCapability = 4466;
    bool mode = false, capability = false;
    for (size_t i = 5; i < spirv.size(); i += std::max<uint32_t>(1u, spirv[i] >> 16)) {  // after the header
        const uint32_t opcode = spirv[i] & 0xffffu, words = spirv[i] >> 16;
        if (opcode == kOpCapability && words == 2 && spirv[i + 1] == kSignedZeroInfNanPreserveCapability)
            capability = true;
        if (opcode == kOpExecutionMode && words == 4 && spirv[i + 2] == kSignedZeroInfNanPreserve &&
            spirv[i + 3] == 32u)
            mode = true;
    }
    EXPECT_EQ(mode, context().keepsIeeeFloats());
    EXPECT_EQ(capability, context().keepsIeeeFloats());
}

TEST_F(Gpu, UnusedFeaturesAreCompiledOutWithoutChangingTheImage) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 2;

    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    GpuRenderer lean(context(), scene, bvh, camera, settings, options);
    options.allFeatures = true;
    GpuRenderer full(context(), scene, bvh, camera, settings, options);
    // The Cornell box has area lights only: no transmission, volumes, textures or punctual lights.
    EXPECT_EQ(lean.features().defines(), std::vector<std::string>{"VKRT_HAS_AREA_LIGHTS"});
    // Every feature but the large primitives' double precision, which follows the scene's geometry
    // (packScene): the Cornell box has neither large triangles nor spheres.
    SceneFeatures every = SceneFeatures::all();
    every.largeTriangles = every.largeSpheres = false;
    EXPECT_EQ(full.features().defines(), every.defines());
    EXPECT_EQ(SceneFeatures::all().defines().size(), 35u);
    for (const std::string& define : lean.defines()) {
        // Besides the scene's features, only how the device reads geometry and adds its ray counts, and on
        // lavapipe the count of loop passes (for llvmpipe's loop budget) and the kernels' chained samples.
        EXPECT_TRUE(define == "VKRT_HAS_AREA_LIGHTS" || define == "VKRT_BOUND_GEOMETRY" ||
                    define == "VKRT_TEXEL_SCENE" || define == "VKRT_SUBGROUP_COUNTERS" ||
                    define == "VKRT_COUNT_LOOP_PASSES" || define == "VKRT_CHAINS_ESCAPES" ||
                    define == "VKRT_IEEE_FLOATS")
            << define;
    }
    EXPECT_LT(lean.spirv().size(), full.spirv().size());
    // glslang keeps function names (OpName) in the SPIR-V until spirv-opt inlines the functions: the lean
    // variant, compiled without the optimizer, has none of the left-out code.
    const std::vector<uint32_t> leanNamed =
        compileShader("trace.comp", lean.defines(), test::shaderCacheDir(), SpirvOptimization::None).spirv;
    const std::vector<uint32_t> fullNamed =
        compileShader("trace.comp", full.defines(), test::shaderCacheDir(), SpirvOptimization::None).spirv;
    auto names = [](const std::vector<uint32_t>& spirv, const std::string& name) {
        const std::string bytes(reinterpret_cast<const char*>(spirv.data()), spirv.size() * 4);
        return bytes.find(name) != std::string::npos;
    };
    for (const char* function :
         {"beerLambert", "refractThrough", "sampleTexture", "arriveFrom", "sphereRoots", "concentricDisk",
          "device_vertexColor", "sampleEnvironment", "environmentPdf", "csgCrossing", "shapeInterval",
          "visibleMicroNormal", "specularBrdf", "sphericalTriangle"}) {
        EXPECT_TRUE(names(fullNamed, function)) << function;
        EXPECT_FALSE(names(leanNamed, function))
            << function << " is compiled in but the scene does not need it";
    }
    const Image a = lean.render().image, b = full.render().image;
    const ImageDifference d = compareImages(a, b, 1e-5, 1e-7);
    EXPECT_EQ(d.fractionOff, 0.0) << "leaving out unused paths must not change the image";
}

// Vertex normals within 1e-4 radians of their faces (the rounding of real files: the walls of
// ../shared/scenes-real's cornell-box-bevy are 4e-5 off) are the faces' own on both devices
// (Scene::smoothNormals): the GPU's shader leaves them out, the CPU reference shades with the faces' normals,
// and a shader with every feature reads the faces' normals packed in their place. Here every vertex normal of
// the Cornell box is tilted 5e-5 radians towards -z. Before, the CPU reference shaded with the tilted
// normals, and those of the walls facing +-x and of the floor took the other branch of orthonormalBasis than
// the GPU's face normals (z below -1e-30 against 0): the two devices' bounces off them went in mirrored
// directions.
TEST_F(Gpu, VertexNormalsWithinRoundingOfTheirFacesShadeAsTheFaces) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    const auto tiltedBy = [&](float angle) {
        Scene tilted = scene;
        for (TriangleShading& s : tilted.shading) {
            for (glm::vec3& n : s.normal) n = glm::normalize(n - glm::vec3(0.0f, 0.0f, angle));
        }
        return tilted;
    };
    const Scene tilted = tiltedBy(5e-5f);
    EXPECT_FALSE(tilted.smoothNormals());
    EXPECT_TRUE(tiltedBy(2e-4f).smoothNormals());  // beyond 1e-4 they are the file's

    const RenderSettings settings = smallCornellPaths(4);
    const Image cpuFaces = ReferenceRenderer(scene, bvh, camera, settings).render().image;
    const Image cpu = ReferenceRenderer(tilted, bvh, camera, settings).render().image;
    EXPECT_EQ(compareImages(cpu, cpuFaces, 0.0, 0.0).fractionOff, 0.0)
        << "the CPU shades with the faces' normals";

    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    GpuRenderer lean(context(), tilted, bvh, camera, settings, options);
    options.allFeatures = true;
    GpuRenderer full(context(), tilted, bvh, camera, settings, options);
    EXPECT_FALSE(lean.features().smoothNormals);
    const Image gpu = lean.render().image;
    EXPECT_EQ(compareImages(full.render().image, gpu, 1e-5, 1e-7).fractionOff, 0.0)
        << "the shader that reads vertex normals is given the faces'";
    test::expectMatchesReference(gpu, cpu, "tilted-normals");
    const ImageDifference d = compareImages(gpu, cpu, 1e-3, 1e-5);
    EXPECT_LE(d.fractionOff, 0.01) << "the devices' samples go the same ways";
}

TEST_F(Gpu, RayTreesAndPathsChainTheSamplesOfEscapingRaysOnLavapipe) {
    // On lavapipe (a CPU device: a SIMD group runs all of a loop's body at every pass any lane needs) both
    // kernels trace the next samples of a SIMD group whose rays all escaped within the same pass of their
    // loop (VKRT_CHAINS_ESCAPES, shaders/trace.comp); a real GPU's kernels are left as they were. The Whitted
    // scene's sky is a third of its image; its samples are the CPU reference's either way, and every one is
    // added, the background's too.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    const bool lavapipe =
        context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU && context().hasSubgroupVote();
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        RenderSettings settings = smallWhitted(8);
        settings.integrator = integrator;
        SCOPED_TRACE(integrator == Integrator::Path ? "paths" : "Whitted");
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        const std::vector<std::string>& defines = renderer.defines();
        EXPECT_EQ(std::find(defines.begin(), defines.end(), "VKRT_CHAINS_ESCAPES") != defines.end(),
                  lavapipe);
        const RenderResult gpu = renderer.render();
        EXPECT_EQ(gpu.rays.nonFiniteSamples, 0u);
        const uint64_t samples =
            static_cast<uint64_t>(settings.width * settings.height * settings.samplesPerPixel);
        EXPECT_EQ(gpu.rays.primary, samples);
        EXPECT_EQ(gpu.samplesKept, samples);
        test::expectMatchesReference(
            gpu.image, ReferenceRenderer(scene, bvh, camera, settings).render().image, "chained");
    }
}

// Sphere roots are found in double only where a sphere is 1024 times as wide as the scene's typical primitive
// (scene_features.cpp), in a shader with every feature too: in float a root is off by float epsilon times the
// distance to the sphere's centre, which a sphere used as the ground makes its radius. The Whitted scene's
// spheres are found in float, with the CPU reference's image. A ground sphere of radius 1e5 under spheres of
// radius 0.3 (the stability suite's case) is found in double where the device has it, within 1e-6 of the
// reference on average (in float, 8e-6).
TEST_F(Gpu, SphereRootsAreInDoubleOnlyWhereASphereIsLarge) {
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    auto inDouble = [](const GpuRenderer& renderer) {
        const std::vector<std::string>& defines = renderer.defines();
        return std::find(defines.begin(), defines.end(), "VKRT_SPHERE_FLOAT64") != defines.end();
    };
    {
        const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
        const RenderSettings settings = smallWhitted(4);
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        EXPECT_TRUE(renderer.features().spheres);
        EXPECT_FALSE(renderer.features().largeSpheres);
        EXPECT_FALSE(inDouble(renderer));
        test::expectMatchesReference(renderer.render().image,
                                     ReferenceRenderer(scene, bvh, camera, settings).render().image,
                                     "spheres in float");
    }
    Scene scene;
    for (const glm::vec3 color : {glm::vec3(0.8f, 0.75f, 0.1f), glm::vec3(0.2f, 0.4f, 0.8f)}) {
        Material material;
        material.baseColor = glm::vec4(color, 1.0f);
        material.metallic = 0.0f;
        scene.materials.push_back(material);
    }
    scene.spheres.push_back({{0.0f, -1e5f, 0.0f}, 1e5f, 0});
    for (int i = 0; i < 5; ++i)
        scene.spheres.push_back({{-2.0f + static_cast<float>(i), 0.3f, 0.0f}, 0.3f, 1});
    PunctualLight light;
    light.position = {2.0, 6.0, 3.0};
    light.intensity = 40.0f;
    scene.lights.push_back(light);
    finalizeScene(scene);
    const FlatBvh bvh = test::bvhFor(scene);
    const Camera camera = lookAtCamera({0.0, 1.5, 5.0}, {0.0, 0.3, 0.0}, 0.7);
    RenderSettings settings;
    settings.width = settings.height = 48;
    settings.samplesPerPixel = 4;
    settings.background = glm::dvec3(0.3, 0.45, 0.7);
    GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
    EXPECT_TRUE(renderer.features().largeSpheres);
    EXPECT_EQ(inDouble(renderer), context().hasShaderFloat64());
    const Image gpu = renderer.render().image;
    const Image cpu = ReferenceRenderer(scene, bvh, camera, settings).render().image;
    test::expectMatchesReference(gpu, cpu, "a ground sphere");
    if (context().hasShaderFloat64()) {
        EXPECT_LT(test::compareWithReference(gpu, cpu).meanRelativeError, 1e-6);
    }
    options.allFeatures = true;
    EXPECT_EQ(inDouble(GpuRenderer(context(), scene, bvh, camera, settings, options)),
              context().hasShaderFloat64());
}

// Rays that start near the world's origin and meet a sphere whose surface passes near it: the camera at the
// origin, a glass ball just in front of it. Roots found in float are off by about float epsilon times the
// distance to the sphere's centre, here far more than the |origin| + t that a hit point's offset otherwise
// scales with (ray.glsl's sphereHitPoint); offset by that alone, the rays refracted into the ball met its
// surface again at once at gaps of 3e-3 and 1e-3 (75% and 42% of the pixels off). The same image as the CPU
// reference's at every gap.
TEST_F(Gpu, RaysIntoASphereNearTheWorldsOriginDoNotMeetItAgain) {
    Material wall, glass;
    wall.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    wall.metallic = 0.0f;
    glass.transmission = 1.0f;
    glass.specularFactor = 1.0f;
    glass.roughness = 0.0f;
    glass.metallic = 0.0f;
    glass.thickness = 1.0f;
    Camera camera;  // at the origin, looking down -z
    camera.yfov = 1.0;
    RenderSettings settings;
    settings.width = settings.height = 48;
    settings.samplesPerPixel = 4;
    settings.integrator = Integrator::Whitted;
    settings.background = glm::dvec3(0.3, 0.45, 0.7);
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    for (const float gap : {1e-2f, 3e-3f, 1e-3f, 3e-4f, 1e-4f}) {
        Scene scene;
        scene.materials = {wall, glass};
        addFlatQuad(scene, {-8.0f, -8.0f, -6.0f}, {8.0f, -8.0f, -6.0f}, {8.0f, 8.0f, -6.0f},
                    {-8.0f, 8.0f, -6.0f}, 0);
        scene.spheres.push_back({{0.0f, 0.0f, -1.0f - gap}, 1.0f, 1});
        PunctualLight light;
        light.position = {3.0, 2.0, -3.0};
        light.intensity = 40.0f;
        scene.lights.push_back(light);
        finalizeScene(scene);
        const FlatBvh bvh = test::bvhFor(scene);
        EXPECT_FALSE(detectFeatures(scene).largeSpheres);
        test::expectMatchesReference(renderGpu(scene, bvh, camera, settings, options).image,
                                     ReferenceRenderer(scene, bvh, camera, settings).render().image,
                                     "a ball " + std::to_string(gap) + " from the origin");
    }
}

TEST_F(Gpu, MirrorOnlyScenesLeaveGgxSamplingOut) {
    // The Whitted scene traces a mirror and smooth glass: its shader has the traced lobes' code but not the
    // sampling of GGX's visible normals and its weights (smaller than the same shader with them), and renders
    // the image of the shader with every feature. The glossy scene's rough metal needs them.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    const RenderSettings settings = smallWhitted(2);
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    GpuRenderer lean(context(), scene, bvh, camera, settings, options);
    EXPECT_TRUE(lean.features().tracedLobes);
    EXPECT_FALSE(lean.features().glossyLobes);
    std::vector<std::string> glossyDefines = lean.defines();
    glossyDefines.push_back("VKRT_HAS_GLOSSY_LOBES");
    const size_t glossyBytes =
        compileShader("trace.comp", glossyDefines, test::shaderCacheDir(), SpirvOptimization::Performance)
            .spirv.size() *
        4;
    EXPECT_LT(lean.spirv().size() * 4 + 1024, glossyBytes);
    options.allFeatures = true;
    GpuRenderer full(context(), scene, bvh, camera, settings, options);
    const ImageDifference d = compareImages(lean.render().image, full.render().image, 1e-5, 1e-7);
    EXPECT_EQ(d.fractionOff, 0.0);

    const auto [glossyScene, glossyBvh, glossyCamera] = ownScene("glossy.gltf", 1.6);
    EXPECT_TRUE(detectFeatures(glossyScene).glossyLobes);
}

// The path kernel's SPIR-V passes (shader_compiler.cpp): all of spirv-opt's performance passes but the SSA
// rewrite of locals stored more than once, which made that kernel 1.8 times as slow on lavapipe. So its
// locals stay variables (few phis, against the performance passes' hundreds), and the rest of the passes
// still shrink the module, which is what lavapipe's pipeline creation takes time over (the Whitted scene's
// path kernel: 123 KiB and 60 ms against 220 KiB and 76 ms with inlining and scalar replacement alone).
// Checked to fail with the passes after the scalar replacement left out.
TEST(ShaderOptimization, PathKernelKeepsItsLocalsAndShrinks) {
    const std::vector<std::string> defines{
        "VKRT_HAS_TRANSMISSION",   "VKRT_HAS_VOLUMES",      "VKRT_HAS_PUNCTUAL_LIGHTS", "VKRT_HAS_SPHERES",
        "VKRT_HAS_ROUGH_SPECULAR", "VKRT_HAS_TRACED_LOBES", "VKRT_TEXEL_SCENE",         "VKRT_PATHS"};
    struct Counts {
        size_t words = 0, functionVariables = 0, phis = 0;
    };
    auto count = [&](SpirvOptimization optimization) {
        const std::vector<uint32_t> spirv = compileShader("trace.comp", defines, "", optimization).spirv;
        Counts c;
        c.words = spirv.size();
        for (size_t at = 5; at < spirv.size();) {  // after the header's five words
            const uint32_t words = spirv[at] >> 16, opcode = spirv[at] & 0xffffu;
            if (words == 0) break;
            if (opcode == 59u && words >= 4 && spirv[at + 3] == 7u)
                ++c.functionVariables;     // OpVariable, Function
            if (opcode == 245u) ++c.phis;  // OpPhi
            at += words;
        }
        return c;
    };
    const Counts none = count(SpirvOptimization::None), keep = count(SpirvOptimization::KeepLocals),
                 performance = count(SpirvOptimization::Performance);
    const std::string counts = "SPIR-V words: glslang's " + std::to_string(none.words) + ", keep locals " +
                               std::to_string(keep.words) + "; function variables " +
                               std::to_string(keep.functionVariables) + ", phis " +
                               std::to_string(keep.phis) + " against the performance passes' " +
                               std::to_string(performance.phis);
    // Inlining alone made the module larger than glslang's (220 KiB against 191); the passes after it take it
    // to about two thirds of glslang's (30,408 words against 47,740; 460 function variables and 43 phis
    // against 687).
    EXPECT_LT(keep.words * 10, none.words * 7) << "the passes should shrink the module; " << counts;
    EXPECT_GT(keep.functionVariables, 20u) << counts;
    EXPECT_LT(keep.phis * 4, performance.phis) << "locals rewritten into phis; " << counts;
}

// A cache entry cut short or changed on disk is compiled again, not handed to the driver: one with a flipped
// byte failed every later render of its scene (VK_ERROR_UNKNOWN from pipeline creation, the cache unnamed).
TEST(ShaderCache, DamagedEntriesAreCompiledAgain) {
    const std::filesystem::path folder = test::temporaryFolder() / "cache";
    const std::vector<std::string> defines = {"VKRT_HAS_SPHERES"};
    const CompiledShader first =
        compileShader("trace.comp", defines, folder.string(), SpirvOptimization::None);
    EXPECT_FALSE(first.fromCache);
    const std::filesystem::path entry = folder / (first.cacheKey + ".spvc");
    ASSERT_TRUE(std::filesystem::exists(entry));
    EXPECT_TRUE(compileShader("trace.comp", defines, folder.string(), SpirvOptimization::None).fromCache);
    const std::string intact = test::readText(entry);
    for (const std::string& damaged :
         {intact.substr(0, intact.size() / 2), intact.substr(0, intact.size() - 4),
          intact.substr(0, 400) + static_cast<char>(intact[400] ^ 0x10) + intact.substr(401)}) {
        test::writeText(entry, damaged);
        const CompiledShader again =
            compileShader("trace.comp", defines, folder.string(), SpirvOptimization::None);
        EXPECT_FALSE(again.fromCache);
        EXPECT_EQ(again.spirv, first.spirv);
        EXPECT_EQ(test::readText(entry), intact) << "the entry is written again";
    }
}

// The cache keeps what was used last within its limit: entries by the time they were written or last read,
// temporary files that a killed writer left behind after an hour, and nothing that is not the cache's.
TEST(ShaderCache, EntriesUsedLongestAgoArePrunedToTheLimit) {
    namespace fs = std::filesystem;
    const fs::path folder = test::temporaryFolder() / "cache";
    fs::create_directories(folder);
    const fs::file_time_type now = fs::file_time_type::clock::now();
    auto file = [&](const std::string& name, size_t bytes, int hoursAgo) {
        test::writeText(folder / name, std::string(bytes, 'x'));
        fs::last_write_time(folder / name, now - std::chrono::hours(hoursAgo));
    };
    file("a.spvc", 100, 3);
    file("b.spvc", 100, 2);
    file("c.spvc", 100, 1);
    file("notes.txt", 1000, 5);
    file("d.spvc.tmp-0000000100000002", 100, 2);
    file("e.spvc.tmp-0000000100000003", 100, 0);
    pruneShaderCache(folder.string(), 250);
    EXPECT_FALSE(fs::exists(folder / "a.spvc"));
    EXPECT_TRUE(fs::exists(folder / "b.spvc"));
    EXPECT_TRUE(fs::exists(folder / "c.spvc"));
    EXPECT_TRUE(fs::exists(folder / "notes.txt"));
    EXPECT_FALSE(fs::exists(folder / "d.spvc.tmp-0000000100000002"))
        << "left by a writer killed two hours ago";
    EXPECT_TRUE(fs::exists(folder / "e.spvc.tmp-0000000100000003")) << "perhaps being written now";
    pruneShaderCache(folder.string(), 100);
    EXPECT_FALSE(fs::exists(folder / "b.spvc"));
    EXPECT_TRUE(fs::exists(folder / "c.spvc"));
    pruneShaderCache((folder / "missing").string(), 0);  // no folder: nothing to do, and no error
}

// Compiling keeps the cache within kShaderCacheBytes, and an entry read is the last to go: one written three
// hours ago and read now outlives a filler entry written two hours ago when a new entry takes the cache over
// its limit.
TEST(ShaderCache, CompilingKeepsTheCacheWithinItsLimitAndReadEntriesLast) {
    namespace fs = std::filesystem;
    const fs::path folder = test::temporaryFolder() / "cache";
    const std::vector<std::string> used = {"VKRT_HAS_SPHERES"},
                                   added = {"VKRT_HAS_SPHERES", "VKRT_HAS_TEXTURES"};
    const CompiledShader first = compileShader("trace.comp", used, folder.string(), SpirvOptimization::None);
    const fs::path usedEntry = folder / (first.cacheKey + ".spvc");
    ASSERT_TRUE(fs::exists(usedEntry));
    const fs::file_time_type now = fs::file_time_type::clock::now();
    fs::last_write_time(usedEntry, now - std::chrono::hours(3));
    const fs::path filler = folder / "filler.spvc";
    test::writeText(filler, "");
    fs::resize_file(filler, kShaderCacheBytes);  // sparse: no disk spent
    fs::last_write_time(filler, now - std::chrono::hours(2));

    EXPECT_TRUE(compileShader("trace.comp", used, folder.string(), SpirvOptimization::None).fromCache);
    const CompiledShader second =
        compileShader("trace.comp", added, folder.string(), SpirvOptimization::None);
    EXPECT_FALSE(second.fromCache);
    EXPECT_TRUE(fs::exists(folder / (second.cacheKey + ".spvc")));
    EXPECT_TRUE(fs::exists(usedEntry)) << "read a moment ago";
    EXPECT_FALSE(fs::exists(filler)) << "the cache would be over its limit";
}

// A scene can turn on any combination of the 34 features, and the committed scenes hold only a few of them.
// So the kernel compiles (glslang, about 30 ms a variant) with every pair of features, each on or off (each
// feature alone, and each left out of all the others), and with 100 more subsets drawn from a fixed seed; for
// both integrators, the three ways of reading the scene and the device's other defines in turn. A combination
// that leaves a name undeclared would otherwise first fail on a user's scene.
TEST(ShaderVariants, EveryPairOfFeaturesCompiles) {
    const std::vector<std::string> all = SceneFeatures::all().defines();
    ASSERT_EQ(all.size(), 35u);
    // Subsets as 64-bit masks: with 32-bit ones, past 32 features the shifts wrapped (undefined, and on x86
    // taken modulo 32), and "every feature" was the first alone.
    ASSERT_LT(all.size(), 64u);
    auto subsetOf = [&](uint64_t bits) {
        std::vector<std::string> subset;
        for (size_t f = 0; f < all.size(); ++f) {
            if ((bits >> f) & 1u) subset.push_back(all[f]);
        }
        return subset;
    };
    const uint64_t every = (uint64_t{1} << all.size()) - 1u;
    std::vector<uint64_t> subsets{0u, every};
    for (size_t f = 0; f < all.size(); ++f) {
        subsets.push_back(uint64_t{1} << f);
        subsets.push_back(every & ~(uint64_t{1} << f));
    }
    std::mt19937_64 draw(13);  // the standard fixes mt19937_64's sequence
    for (int k = 0; k < 100; ++k) subsets.push_back(draw() & every);
    EXPECT_EQ(subsetOf(every), all);

    const std::vector<std::vector<std::string>> accesses{{"VKRT_TEXEL_SCENE"}, {"VKRT_BOUND_GEOMETRY"}, {}};
    size_t compiled = 0;
    for (size_t row = 0; row < subsets.size(); ++row) {
        std::vector<std::string> defines = subsetOf(subsets[row]);
        for (const std::string& define : accesses[row % accesses.size()]) defines.push_back(define);
        if (row % 2 == 0) defines.insert(defines.end(), {"VKRT_SUBGROUP_COUNTERS", "VKRT_COUNT_LOOP_PASSES"});
        if (std::find(defines.begin(), defines.end(), "VKRT_HAS_SPHERES") != defines.end() && row % 4 < 2)
            defines.push_back("VKRT_SPHERE_FLOAT64");
        if (row % 3 != 0) defines.push_back("VKRT_PIXEL_FILTER " + std::to_string(row % 3) + "u");
        if (std::find(defines.begin(), defines.end(), "VKRT_HAS_CSG") != defines.end() && row % 5 < 3)
            defines.push_back("VKRT_SOLID_SHAPES " + std::to_string(2 + row % 6));
        for (const bool paths : {false, true}) {
            std::vector<std::string> variant = defines;
            if (paths) variant.push_back("VKRT_PATHS");
            try {
                compileShader("trace.comp", variant, "", SpirvOptimization::None);
                ++compiled;
            } catch (const ShaderError& e) {
                ADD_FAILURE() << "defines " << ::testing::PrintToString(variant) << ":\n" << e.what();
            }
        }
    }
    EXPECT_EQ(compiled, 2 * subsets.size());
}

TEST_F(Gpu, TexelStorageAndAddressedScenesGiveTheSameImage) {
    // Every array read each way: triangles, spheres, a punctual light and the dielectric albedo table
    // (whitted), area lights (cornell), textures, vertex normals and colours, second texture coordinates and
    // the GGX albedo table (textures), the environment map and its tables (environment), solids, their shapes
    // and a shape as a light (csg), primitives' poses (motion-blur), tangents and the sheen table (surfaces).
    // (Shapes' poses: Gpu.MotionBlurStreakIsVelocityTimesShutter.) The arrays are read by the same code in
    // both kernels, so the path kernel reads them all and Whitted's reads the Whitted scene's (each variant's
    // JIT compilation is most of the test's time: 42 variants took 100 s of ctest -j2, 24 take about half).
    for (const std::string file : {"whitted.gltf", "cornell.gltf", "textures.gltf", "environment.gltf",
                                   "csg.gltf", "motion-blur.gltf", "surfaces.gltf"}) {
        auto [scene, bvh, camera] = ownScene(file.c_str(), 4.0 / 3.0);
        if (file == "environment.gltf") {
            // A map brighter towards its top and one side, so that importance sampling reads its tables.
            std::vector<glm::vec3> texels;
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 16; ++x)
                    texels.push_back(glm::vec3(0.1f + (8 - y) * (x < 4 ? 2.0f : 0.3f)));
            scene.environment = makeEnvironmentMap("test", 16, 8, texels, 30.0, 1.0);
        }
        for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
            if (integrator == Integrator::Whitted && file != "whitted.gltf") continue;
            RenderSettings settings = smallWhitted(2);
            settings.integrator = integrator;
            std::vector<Image> images;
            for (const SceneAccess access :
                 {SceneAccess::Texels, SceneAccess::Storage, SceneAccess::Addresses}) {
                GpuRenderOptions options;
                options.sceneAccess = access;
                GpuRenderReport report;
                images.push_back(renderGpu(scene, bvh, camera, settings, options, &report).image);
                EXPECT_EQ(report.sceneAccess, access) << file << ": " << sceneAccessName(access);
            }
            EXPECT_EQ(compareImages(images[0], images[1], 1e-6, 1e-8).fractionOff, 0.0) << file;
            EXPECT_EQ(compareImages(images[0], images[2], 1e-6, 1e-8).fractionOff, 0.0) << file;
        }
    }
}

TEST_F(Gpu, DevicesReadTheSceneTheirBestWay) {
    // Texel buffers, the fastest way on lavapipe and on the one GPU measured (an H200), where they fit.
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    GpuRenderReport report;
    renderGpu(scene, bvh, camera, smallWhitted(1), {}, &report);
    EXPECT_EQ(report.sceneAccess, SceneAccess::Texels);
}

// A CPU device's memory is the process's own, and a large buffer asks for huge pages before it is first
// written (gpu_buffer.cpp): first touching 4 KiB pages costs about 20 us each on a virtual machine.
TEST_F(Gpu, LargeBuffersOfACpuDeviceAreOnHugePages) {
    if (context().properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU)
        GTEST_SKIP() << "a GPU's own memory";
    if (!test::hugePagesOnRequest()) GTEST_SKIP() << "transparent huge pages are not given on request";
    if (!test::hugePagesGivenNow()) GTEST_SKIP() << "the kernel gives no huge pages now";
    constexpr size_t kBytes = size_t{64} << 20;
    uintptr_t where = 0;
    const GpuBuffer buffer(context(), kBytes, [&](void* mapped) {
        std::memset(mapped, 1, kBytes);
        where = reinterpret_cast<uintptr_t>(mapped);
    });
    ASSERT_NE(where, 0u);
    if (!test::anonymousMemoryAt(where)) GTEST_SKIP() << "the device's memory is shared memory (a memfd)";
    // All of it but the unaligned ends (each less than a huge page).
    EXPECT_GE(test::hugePageBytesIn(where, where + kBytes), kBytes - (size_t{4} << 20));
}

// Downloads read mapped memory where the host caches it and copy through cached host memory where it does not
// (a discrete GPU's memory over the bus), and uploads go through a staging copy where the host cannot map the
// buffer; both ways give the buffer's bytes, from any offset.
TEST_F(Gpu, BuffersWriteAndReadTheSameMappedOrStaged) {
    std::vector<uint32_t> values(100000);
    for (size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint32_t>(i * 2654435761u);
    const GpuBuffer buffer(context(), values);
    const size_t first = 5003, count = 40000;  // 160 KB: more than is read in place uncached
    std::vector<uint32_t> read(count), staged(count);
    buffer.download(read.data(), count * sizeof(uint32_t), first * sizeof(uint32_t));
    buffer.downloadStaged(staged.data(), count * sizeof(uint32_t), first * sizeof(uint32_t));
    const std::vector<uint32_t> expected(values.begin() + first, values.begin() + first + count);
    EXPECT_EQ(read, expected);
    EXPECT_EQ(staged, expected);
    uint32_t one = 0;
    buffer.downloadStaged(&one, sizeof(one), (values.size() - 1) * sizeof(uint32_t));
    EXPECT_EQ(one, values.back());
    // Written through a staging copy (GPUs' device buffers, which the host does not map), read both ways.
    GpuBuffer written(context(), values.size() * sizeof(uint32_t));
    written.fillZero();
    written.uploadStaged(values.data() + first, count * sizeof(uint32_t), first * sizeof(uint32_t));
    std::vector<uint32_t> back(values.size());
    written.download(back.data(), back.size() * sizeof(uint32_t));
    EXPECT_EQ(std::vector<uint32_t>(back.begin() + first, back.begin() + first + count), expected);
    EXPECT_EQ(back[first - 1], 0u);
    EXPECT_EQ(back[first + count], 0u);
    written.downloadStaged(back.data(), back.size() * sizeof(uint32_t));
    EXPECT_EQ(std::vector<uint32_t>(back.begin() + first, back.begin() + first + count), expected);
}

TEST_F(Gpu, DeviceBuffersAreMappedUnlessStagedAreAsked) {
    // Mapped where the device lets the host see its memory; staged (where only the device's copies reach
    // them) when asked (ray_benchmark --device-buffers), and the same bytes either way.
    EXPECT_TRUE(context().mapsDeviceBuffers());
    for (const DeviceBuffers way : {DeviceBuffers::Mapped, DeviceBuffers::Staged}) {
        ContextOptions options;
        options.deviceBuffers = way;
        const VulkanContext asked(options);
        EXPECT_EQ(asked.mapsDeviceBuffers(), way == DeviceBuffers::Mapped);
        const std::vector<uint32_t> values{1u, 2u, 3u, 0xdeadbeefu};
        const GpuBuffer buffer(asked, values);
        std::vector<uint32_t> back(values.size());
        buffer.download(back.data(), back.size() * sizeof(uint32_t));
        EXPECT_EQ(back, values);
    }
}

TEST_F(Gpu, RayCountsAreTheSameSummedPerSubgroupOrPerInvocation) {
    if (!context().hasSubgroupArithmetic()) GTEST_SKIP() << "the device cannot sum across subgroups";
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        RenderSettings settings = smallWhitted(3);
        settings.integrator = integrator;
        GpuRenderOptions perInvocation;
        perInvocation.subgroupCounters = false;
        const RenderResult a = renderGpu(scene, bvh, camera, settings, {});
        const RenderResult b = renderGpu(scene, bvh, camera, settings, perInvocation);
        EXPECT_EQ(a.rays.primary, static_cast<uint64_t>(settings.width) * settings.height * 3u);
        EXPECT_GT(a.rays.secondary, 0u);
        EXPECT_GT(a.rays.shadow, 0u);
        EXPECT_EQ(a.rays.primary, b.rays.primary);
        EXPECT_EQ(a.rays.secondary, b.rays.secondary);
        EXPECT_EQ(a.rays.shadow, b.rays.shadow);
        EXPECT_EQ(a.rays.nonFiniteSamples, b.rays.nonFiniteSamples);
        EXPECT_EQ(compareImages(a.image, b.image, 1e-6, 1e-8).fractionOff, 0.0);
    }
}

TEST_F(Gpu, ChunkingDoesNotChangeTheImage) {
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    const RenderSettings settings = smallWhitted(6);
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

TEST_F(Gpu, DispatchesGrowAcrossSweepsOfTheImage) {
    // Dispatches double until they take the target time. The first sweep of 32 rows ends with one row left
    // over (1 + 2 + 4 + 8 + 16 + 1); growth from there is capped by the largest dispatch so far, not that
    // last one, so the next sweeps take all rows at 1, 2, 4 and 8 samples: 10 dispatches. Capped by the
    // last, the ramp began again from one row after every sweep: 24.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 1.0);
    RenderSettings settings = smallWhitted(16);
    settings.height = 32;
    GpuRenderOptions options;
    options.targetDispatchMs = 1e9;
    GpuRenderReport report;
    const RenderResult result = renderGpu(scene, bvh, camera, settings, options, &report);
    EXPECT_EQ(report.dispatches, 10u);
    EXPECT_EQ(report.mostSamplesInDispatch, 8u);
    EXPECT_EQ(result.fewestSamples, 16u);
    EXPECT_EQ(result.mostSamples, 16u);
}

TEST_F(Gpu, DispatchTimeComesFromTheDevice) {
    // 100 ms on lavapipe, which has no watchdog; 50 on a GPU; or what the options say.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    const RenderSettings settings = smallWhitted(1);
    const bool cpuDevice = context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    EXPECT_EQ(GpuRenderer(context(), scene, bvh, camera, settings).report().targetDispatchMs,
              cpuDevice ? 100.0 : 50.0);
    GpuRenderOptions options;
    options.targetDispatchMs = 20.0;
    EXPECT_EQ(GpuRenderer(context(), scene, bvh, camera, settings, options).report().targetDispatchMs, 20.0);
}

TEST_F(Gpu, WhittedBatchesTakeSeveralSamplesOverFewerRows) {
    // 128 x 64 pixels and dispatches of at least 8 rows: after the first sample's sweep (1, 2, 4, 8, 16, 32
    // and 1 rows), the doubling allows 64 row-samples, taken as 8 samples over 8 rows rather than one sample
    // over 64; the image is that of a render in one dispatch a sample.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 2.0);
    RenderSettings settings = smallWhitted(16);
    settings.width = 128;
    settings.height = 64;
    GpuRenderOptions options, oneSample;
    options.targetDispatchMs = 1e9;
    options.minDispatchInvocations = 128 * 8;
    oneSample.targetDispatchMs = 1e-6;
    GpuRenderReport report, oneSampleReport;
    const Image a = renderGpu(scene, bvh, camera, settings, options, &report).image;
    const Image b = renderGpu(scene, bvh, camera, settings, oneSample, &oneSampleReport).image;
    EXPECT_EQ(report.mostSamplesInDispatch, 8u);
    EXPECT_EQ(oneSampleReport.mostSamplesInDispatch, 1u);
    // lavapipe: the kernel counted its loop passes, and the batches kept within a quarter of llvmpipe's
    // budget.
    if (context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        EXPECT_GT(report.loopPassesPerSample, 0u);
        EXPECT_LE(report.mostSamplesInDispatch * report.loopPassesPerSample, VKRT_LLVMPIPE_LOOP_BUDGET / 4);
    }
    EXPECT_EQ(compareImages(a, b, 1e-5, 1e-7).fractionOff, 0.0);
}

TEST_F(Gpu, SpreadWorkgroupsTakeEveryTileOnce) {
    // 128 x 64 pixels; the dispatches double in size whatever they take, to batches of several samples over
    // all 64 rows (16 tiles a band of eight rows): each tile taken by another workgroup than in order, the
    // same dispatches, and the image the same to the bit.
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 2.0);
    RenderSettings settings = smallWhitted(16);
    settings.width = 128;
    settings.height = 64;
    GpuRenderOptions inOrder;
    inOrder.targetDispatchMs = 1e9;
    inOrder.minDispatchInvocations = 128 * 64;
    inOrder.workgroupOrder = WorkgroupOrder::InOrder;
    GpuRenderOptions spread = inOrder;
    spread.workgroupOrder = WorkgroupOrder::Spread;
    GpuRenderReport inOrderReport, spreadReport, autoReport;
    const Image a = renderGpu(scene, bvh, camera, settings, inOrder, &inOrderReport).image;
    const Image b = renderGpu(scene, bvh, camera, settings, spread, &spreadReport).image;
    EXPECT_EQ(inOrderReport.workgroupOrder, WorkgroupOrder::InOrder);
    EXPECT_EQ(spreadReport.workgroupOrder, WorkgroupOrder::Spread);
    EXPECT_EQ(inOrderReport.dispatches, spreadReport.dispatches);
    EXPECT_GT(spreadReport.mostSamplesInDispatch, 1u);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], b.pixels[i]) << "pixel " << i;
    // By the device: spread where lavapipe's threads each take one contiguous run of workgroups.
    renderGpu(scene, bvh, camera, smallWhitted(1), {}, &autoReport);
    const bool cpuDevice = context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    EXPECT_EQ(autoReport.workgroupOrder, cpuDevice ? WorkgroupOrder::Spread : WorkgroupOrder::InOrder);
}

// One dispatch of a simulated render (DispatchPlanner without a device).
struct PlannedDispatch {
    uint32_t sample, samples, row, rows;
    double ms;
};

// Samples [first, end) of an image of `height` rows, planned as GpuRenderer::renderTile does, each
// row-sample costing costMs(row) milliseconds; `lostAt`: the dispatch (from 0) that reports lost samples.
std::vector<PlannedDispatch> planRender(DispatchPlanner& planner, uint32_t height, uint32_t first,
                                        uint32_t end, uint32_t most, double (*costMs)(uint32_t),
                                        int lostAt = -1) {
    std::vector<PlannedDispatch> dispatches;
    for (uint32_t s = first; s < end;) {
        const uint32_t samples = planner.batchSamples(s, std::min(end - s, most), 0, height);
        for (uint32_t row = 0; row < height;) {
            const uint32_t rows = planner.rows(row, height, samples);
            double ms = 0.0;
            for (uint32_t r = row; r < row + rows; ++r) ms += samples * costMs(r);
            planner.record(row, rows, samples, ms);
            if (static_cast<int>(dispatches.size()) == lostAt) planner.samplesLost();
            dispatches.push_back({s, samples, row, rows, ms});
            row += rows;
        }
        s += samples;
    }
    return dispatches;
}

double evenCost(uint32_t) {
    return 0.01;
}
// A band of rows ten times as costly as the rest (glass in front of sky).
double bandedCost(uint32_t row) {
    return row >= 96 && row < 160 ? 0.1 : 0.01;
}

TEST(DispatchPlanner, FirstSampleSweepsEveryRowBeforeBatchesTakeSeveral) {
    // 256 rows at 0.01 ms a row-sample: a whole image at one sample takes 2.56 ms, under the 50 ms a
    // dispatch is for, so later batches take 16 samples over at least 16 rows.
    DispatchPlanner planner(256, 50.0, 16);
    const std::vector<PlannedDispatch> dispatches = planRender(planner, 256, 0, 49, 16, evenCost);
    ASSERT_FALSE(dispatches.empty());
    EXPECT_EQ(dispatches.front().rows, 1u);  // the first: one row at one sample
    EXPECT_EQ(dispatches.front().samples, 1u);
    uint32_t rowsAtFirstSample = 0;
    for (const PlannedDispatch& d : dispatches) {
        if (d.sample == 0) {
            EXPECT_EQ(d.samples, 1u);
            rowsAtFirstSample += d.rows;
        }
    }
    EXPECT_EQ(rowsAtFirstSample, 256u);
    // Growth: at most twice the largest dispatch before, in rows x samples.
    double largest = 1.0;
    for (const PlannedDispatch& d : dispatches) {
        EXPECT_LE(d.rows * d.samples, 2.0 * largest) << d.sample << " " << d.row;
        largest = std::max(largest, static_cast<double>(d.rows * d.samples));
    }
    EXPECT_EQ(dispatches.back().samples, 16u);
    EXPECT_EQ(dispatches.back().rows, 256u);  // 16 samples of the whole image fit in 50 ms
}

TEST(DispatchPlanner, BatchesTakeSamplesBeforeRows) {
    // 0.3 ms a row-sample: 50 ms hold about 166 row-samples, fewer than the image's 256 rows. A batch then
    // takes 16 samples over a few rows (at least 8) rather than one sample over 166 rows.
    DispatchPlanner planner(256, 50.0, 8);
    const auto slow = [](uint32_t) { return 0.3; };
    const std::vector<PlannedDispatch> dispatches = planRender(planner, 256, 0, 33, 16, +slow);
    for (const PlannedDispatch& d : dispatches) {
        if (d.sample == 0) continue;
        EXPECT_EQ(d.samples, 16u) << d.sample;
        EXPECT_LE(d.ms, 50.0 + 1e-9) << d.sample << " " << d.row;
        if (d.row + d.rows < 256) {
            EXPECT_GE(d.rows, 8u) << d.sample << " " << d.row;
        }
    }
}

TEST(DispatchPlanner, CostlyBandsGetFewerRows) {
    // Rows 96 to 159 cost ten times the rest. Each row keeps the cost of the dispatch that last traced it, so
    // after the first sweep the band's dispatches hold fewer rows, and none of several rows runs to twice the
    // target (a dispatch that mixes the band with cheaper rows leaves them all its mean cost, so the
    // estimates stay that coarse).
    DispatchPlanner planner(256, 5.0, 1);
    const std::vector<PlannedDispatch> dispatches = planRender(planner, 256, 0, 9, 2, bandedCost);
    double bandRows = 0.0, otherRows = 0.0;
    int band = 0, other = 0;
    for (const PlannedDispatch& d : dispatches) {
        if (d.sample == 0 || d.row + d.rows == 256) continue;  // the first sweep, and sweeps' last dispatches
        if (d.rows > 1) {
            EXPECT_LT(d.ms, 10.0) << d.sample << " " << d.row << " " << d.rows;
        }
        const bool inBand = d.row >= 96 && d.row + d.rows <= 160;
        (inBand ? bandRows : otherRows) += d.rows;
        ++(inBand ? band : other);
    }
    ASSERT_GT(band, 0);
    ASSERT_GT(other, 0);
    EXPECT_LT(bandRows / band, 0.5 * otherRows / other);
}

TEST(DispatchPlanner, LoopBudgetBoundsTheSamplesOfABatch) {
    // With llvmpipe's budget, batches take one sample until the kernel has reported the loop passes a sample
    // takes, then as many as fit a quarter of the budget: 65535 / 4 / 3000 = 5.
    DispatchPlanner planner(64, 1e9, 1, 65535);
    EXPECT_EQ(planner.batchSamples(5, 16, 0, 64), 1u);
    planner.loopPassesPerSample(3000);
    planner.record(0, 64, 1, 1.0);  // leaves the time budget room for the 16 samples
    planner.record(0, 64, 1, 1.0);
    EXPECT_EQ(planner.batchSamples(5, 16, 0, 64), 5u);
    planner.loopPassesPerSample(20000);  // even one sample over a quarter of the budget: one
    EXPECT_EQ(planner.batchSamples(5, 16, 0, 64), 1u);
    DispatchPlanner unbudgeted(64, 1e9, 1);
    unbudgeted.record(0, 64, 1, 1.0);
    unbudgeted.record(0, 64, 1, 1.0);
    EXPECT_EQ(unbudgeted.batchSamples(5, 16, 0, 64), 16u);
}

TEST(DispatchPlanner, LostSamplesMakeBatchesOfOneSample) {
    DispatchPlanner planner(64, 50.0, 4);
    // Lost samples reported at the tenth dispatch, in the batches after the first sweep.
    const std::vector<PlannedDispatch> dispatches = planRender(planner, 64, 0, 40, 16, evenCost, 9);
    ASSERT_GT(dispatches.size(), 10u);
    EXPECT_GT(dispatches[9].samples, 1u);
    const uint32_t batchAfterLoss = dispatches[9].sample + dispatches[9].samples;
    for (const PlannedDispatch& d : dispatches) {
        if (d.sample >= batchAfterLoss) {
            EXPECT_EQ(d.samples, 1u) << d.sample;
        }
    }
}

// The widest gap between the items one thread takes, over the threads, when `threads` threads split a
// dispatch of `items` spread for `spreadFor` as lavapipe does (contiguous runs of workgroups / threads in
// launch order, the remainder one at a time). The ends of the range count as items.
uint32_t widestThreadGap(uint32_t items, uint32_t spreadFor, uint32_t threads) {
    // Which thread takes each item (workgroups in launch order, column by column), then the items in order,
    // each thread's gap since its last.
    const SpreadGrid grid = spreadGrid(items, spreadFor);
    const uint32_t groups = grid.perColumn * grid.columns, run = groups / threads;
    std::vector<uint32_t> owner(items);
    for (uint32_t g = 0; g < groups; ++g) {
        const uint32_t item = shading::spreadItem(g % grid.perColumn, g / grid.perColumn, grid.columns);
        if (item < items)
            owner[item] = run > 0 && g < run * threads ? g / run : (g - run * threads) % threads;
    }
    std::vector<int64_t> last(threads, -1);
    int64_t widest = 0;
    for (uint32_t item = 0; item < items; ++item) {
        widest = std::max(widest, item - last[owner[item]]);
        last[owner[item]] = item;
    }
    for (const int64_t item : last) widest = std::max(widest, items - item);
    return static_cast<uint32_t>(widest);
}

TEST(WorkgroupOrder, SpreadRunsTakeItemsFromTheWholeRange) {
    for (uint32_t items = 1; items <= 600; ++items) {
        for (uint32_t spreadFor = 1; spreadFor <= 32; ++spreadFor) {
            // Every item once, by a workgroup of the grid; no column without items.
            const SpreadGrid grid = spreadGrid(items, spreadFor);
            ASSERT_LE(grid.columns, std::min(items, spreadFor));
            ASSERT_LT(grid.perColumn * grid.columns - items, grid.columns)
                << items << " items for " << spreadFor;
            std::vector<bool> taken(items, false);
            for (uint32_t column = 0; column < grid.columns; ++column) {
                for (uint32_t k = 0; k < grid.perColumn; ++k) {
                    const uint32_t item = shading::spreadItem(k, column, grid.columns);
                    if (item >= items) continue;
                    ASSERT_FALSE(taken[item])
                        << items << " items for " << spreadFor << ": item " << item << " twice";
                    taken[item] = true;
                }
            }
            ASSERT_EQ(std::count(taken.begin(), taken.end(), true), static_cast<long>(items));
            // Each thread's run reaches over the whole range, its items at most twice the thread count apart
            // (in order, one thread's are one contiguous items / threads of the range); where the threads
            // divide the count spread for (more processors than lavapipe's threads), at most twice that
            // count.
            if (items < 2 * spreadFor) continue;
            EXPECT_LE(widestThreadGap(items, spreadFor, spreadFor), 2 * spreadFor) << items << " items";
            for (uint32_t threads = 2; threads < spreadFor; ++threads) {
                if (spreadFor % threads == 0) {
                    EXPECT_LE(widestThreadGap(items, spreadFor, threads), 2 * spreadFor)
                        << items << " items, " << threads << " threads";
                }
            }
        }
    }
    // In order, the first of two threads takes the first half, and the second's items start half way.
    EXPECT_EQ(widestThreadGap(64, 1, 2), 33u);
    EXPECT_EQ(widestThreadGap(64, 2, 2), 2u);
}

TEST(WorkgroupOrder, SpreadForLavapipesThreads) {
    // LP_NUM_THREADS when it is set (as lavapipe reads it), else one thread per processor; in order, one.
    const char* before = std::getenv("LP_NUM_THREADS");
    const std::string saved = before ? before : "";
    setenv("LP_NUM_THREADS", "3", 1);
    EXPECT_EQ(spreadThreads(WorkgroupOrder::Spread), 3u);
    EXPECT_EQ(workgroupOrderName(WorkgroupOrder::Spread), "spread over 3 threads");
    EXPECT_EQ(spreadThreads(WorkgroupOrder::InOrder), 1u);
    EXPECT_EQ(workgroupOrderName(WorkgroupOrder::InOrder), "in order");
    unsetenv("LP_NUM_THREADS");
    EXPECT_EQ(spreadThreads(WorkgroupOrder::Spread), std::max(1u, std::thread::hardware_concurrency()));
    if (before) setenv("LP_NUM_THREADS", saved.c_str(), 1);
}

TEST_F(Gpu, TimeLimitStopsAfterTheDispatchThatCrossesIt) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 100000;
    GpuRenderReport report;
    const RenderResult result = renderGpu(scene, bvh, camera, settings, {}, &report, StopCondition(nullptr, 1e-6));
    // The first dispatch is one row at one sample; the limit ends the render after it, part way through the
    // first pass.
    EXPECT_EQ(result.stopped, StopReason::TimeLimit);
    EXPECT_EQ(report.dispatches, 1u);
    EXPECT_EQ(result.fewestSamples, 0u);
    EXPECT_EQ(result.mostSamples, 1u);
    EXPECT_EQ(result.rays.primary, 32u);
    // Row 0 is that of a one-sample render; the rest have no samples yet and are black.
    settings.samplesPerPixel = 1;
    const Image oneSample = renderGpu(scene, bvh, camera, settings).image;
    for (int x = 0; x < 32; ++x) {
        EXPECT_EQ(result.image.at(x, 0), oneSample.at(x, 0)) << x;
        EXPECT_EQ(result.image.at(x, 16), glm::vec3(0.0f)) << x;
    }
}

// A render stopped part way through a pass is, pixel by pixel, the render of the samples each pixel got: rows
// the last pass reached equal a render of `mostSamples`, the others one of `fewestSamples`, exactly.
TEST_F(Gpu, StoppedRenderAveragesEachPixelOverItsOwnSamples) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    const RenderSettings settings = smallCornellPaths(64);
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    std::atomic<bool> stopFlag{false};
    RenderResult stopped;
    {
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        // Progress counts rows x samples (one sample per pass for paths): stop in the second pass or later, at
        // the first dispatch that ends part way through its pass.
        stopped = renderer.render(
            [&](uint64_t done, uint64_t) { stopFlag = stopFlag || (done > 24 && done % 24 != 0); }, {}, 0.0,
            StopCondition(&stopFlag, 0.0));
    }
    ASSERT_EQ(stopped.stopped, StopReason::Requested);
    ASSERT_EQ(stopped.mostSamples, stopped.fewestSamples + 1);
    RenderSettings fewer = settings, more = settings;
    fewer.samplesPerPixel = static_cast<int>(stopped.fewestSamples);
    more.samplesPerPixel = static_cast<int>(stopped.mostSamples);
    const Image a = fewer.samplesPerPixel > 0 ? renderGpu(scene, bvh, camera, fewer).image : Image(24, 24);
    const Image b = renderGpu(scene, bvh, camera, more).image;
    int rowsWithMore = 0;
    for (int y = 0; y < 24; ++y) {
        const bool more = stopped.image.at(0, y) == b.at(0, y) && stopped.image.at(0, y) != a.at(0, y);
        rowsWithMore += more ? 1 : 0;
        for (int x = 0; x < 24; ++x)
            ASSERT_EQ(stopped.image.at(x, y), (more ? b : a).at(x, y)) << x << ", " << y;
    }
    EXPECT_GT(rowsWithMore, 0);
    EXPECT_LT(rowsWithMore, 24);
}

// Room for the scene and `rows` rows of the image's accumulation, no more.
uint64_t roomForRows(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh, int width,
                     int rows) {
    const DeviceMemoryPlan whole =
        planDeviceMemory(context, sceneBufferNeed(packScene(scene, bvh)), width, 1);
    return whole.need.total() + static_cast<uint64_t>(rows - 1) * width * kAccumulationBytesPerPixel;
}

TEST_F(Gpu, TiledRenderEqualsTheWholeImage) {
    const auto [scene, bvh, camera] = ownScene("whitted.gltf", 4.0 / 3.0);
    const RenderSettings settings = smallWhitted(5);
    GpuRenderOptions tiled;
    tiled.maxDeviceMemoryBytes = roomForRows(context(), scene, bvh, settings.width, 7);
    GpuRenderReport wholeReport, tiledReport;
    const Image a = renderGpu(scene, bvh, camera, settings, {}, &wholeReport).image;
    const RenderResult b = renderGpu(scene, bvh, camera, settings, tiled, &tiledReport);
    EXPECT_EQ(wholeReport.memory.tiles, 1u);
    EXPECT_EQ(tiledReport.memory.tiles, 5u);  // 30 rows in bands of at most 7: 5 bands of 6
    EXPECT_EQ(tiledReport.memory.tileRows, 6u);
    EXPECT_EQ(tiledReport.hostCopies, 20u);  // passes to 1, 2, 4 and 5 samples, each tile copied once a pass
    EXPECT_LE(tiledReport.memory.need.total(), tiled.maxDeviceMemoryBytes);
    EXPECT_EQ(b.fewestSamples, 5u);
    EXPECT_EQ(b.mostSamples, 5u);
    EXPECT_EQ(compareImages(a, b.image, 1e-5, 1e-7).fractionOff, 0.0);
}

// With checkpoints, every tile reaches each power of two before the checkpoint: the images match the whole
// image's checkpoints.
TEST_F(Gpu, TiledCheckpointsSeeTheWholeImage) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    const RenderSettings settings = smallCornellPaths(4);
    auto checkpoints = [&](const GpuRenderOptions& options) {
        std::vector<std::pair<uint32_t, Image>> seen;
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        renderer.render({}, [&](uint32_t samples, double, double, const Image& image) {
            seen.emplace_back(samples, image);
        });
        return seen;
    };
    GpuRenderOptions whole, tiled;
    whole.shaderCacheDir = tiled.shaderCacheDir = test::shaderCacheDir();
    tiled.maxDeviceMemoryBytes = roomForRows(context(), scene, bvh, settings.width, 10);
    const auto a = checkpoints(whole), b = checkpoints(tiled);
    ASSERT_EQ(a.size(), 3u);  // 1, 2 and 4 samples
    ASSERT_EQ(b.size(), a.size());
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(b[i].first, a[i].first);
        EXPECT_EQ(compareImages(a[i].second, b[i].second, 1e-5, 1e-7).fractionOff, 0.0)
            << a[i].first << " spp";
    }
}

TEST_F(Gpu, RenderThatDoesNotFitIsRefusedBeforeAllocating) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 64;
    GpuRenderOptions options;
    options.maxDeviceMemoryBytes = roomForRows(context(), scene, bvh, settings.width, 1) - 1;
    const uint64_t heldBefore = context().allocatedBytes();
    try {
        GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
        FAIL() << "not even one row fits";
    } catch (const MemoryError& e) {
        EXPECT_NE(std::string(e.what()).find("(--max-device-memory)"), std::string::npos) << e.what();
    }
    EXPECT_EQ(context().allocatedBytes(), heldBefore);
    options.maxDeviceMemoryBytes += 1;
    EXPECT_NO_THROW(GpuRenderer(context(), scene, bvh, camera, settings, options));
}

// A device lost part way: the tiles copied before it are kept exactly. A tiled image's passes double its
// samples (1, then 2): lost in the second pass, the tile it finished has both samples and the others one.
TEST_F(Gpu, LostDeviceKeepsTheTilesCopiedBeforeIt) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = 2;
    GpuRenderOptions options;
    options.targetDispatchMs = 1e-6;  // one row, one sample per dispatch: 8 x 2 dispatches per tile
    options.hostCopyEveryMs = 1e9;    // copies only when the tile changes
    options.maxDeviceMemoryBytes = roomForRows(context(), scene, bvh, settings.width, 8);
    const Image whole = renderGpu(scene, bvh, camera, settings, options).image;
    RenderSettings once = settings;
    once.samplesPerPixel = 1;
    const Image first = renderGpu(scene, bvh, camera, once, options).image;
    options.simulateDeviceLossAtDispatch = 3 * 8 + 8 + 1;  // the second pass's first of the second tile
    GpuRenderReport report;
    const RenderResult lost = renderGpu(scene, bvh, camera, settings, options, &report);
    EXPECT_EQ(report.memory.tiles, 3u);
    EXPECT_EQ(lost.stopped, StopReason::DeviceLost);
    EXPECT_EQ(report.deviceLost, "the device was lost (simulated at dispatch 33)");
    EXPECT_EQ(lost.fewestSamples, 1u);
    EXPECT_EQ(lost.mostSamples, 2u);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x)
            ASSERT_EQ(lost.image.at(x, y), y < 8 ? whole.at(x, y) : first.at(x, y)) << x << ", " << y;
}

// A tiled render stopped a quarter of the way through (here by its progress; a time limit or an interrupt
// alike) has samples in every row: its passes double the samples of every tile in turn (all the samples of
// one tile before the next left three of its four tiles black).
TEST_F(Gpu, TiledRenderStoppedEarlyHasSamplesEverywhere) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 16;
    GpuRenderOptions options;
    options.shaderCacheDir = test::shaderCacheDir();
    options.targetDispatchMs = 1e-6;  // one row, one sample per dispatch
    options.maxDeviceMemoryBytes = roomForRows(context(), scene, bvh, settings.width, 8);
    std::atomic<bool> stopNow{false};
    GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
    const RenderResult result =
        renderer.render([&](uint64_t done, uint64_t total) { stopNow = stopNow || 4 * done >= total; }, {},
                        0.0, StopCondition(&stopNow, 0.0));
    EXPECT_EQ(renderer.report().memory.tiles, 4u);
    EXPECT_EQ(result.stopped, StopReason::Requested);
    EXPECT_GE(result.fewestSamples, 2u);  // passes to 1, 2 and 4 samples: the third a quarter of the way
    EXPECT_LT(result.mostSamples, 16u);
}

// Copies by time keep the samples of a render in one tile: with a copy after every dispatch, a device lost
// at dispatch k keeps exactly the k - 1 dispatches before it, each row averaged over its own samples.
TEST_F(Gpu, LostDeviceKeepsWhatTheLastCopyHeld) {
    const auto [scene, bvh, camera] = ownScene("cornell.gltf", 1.0);
    RenderSettings settings;
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 3;
    GpuRenderOptions options;
    options.targetDispatchMs = 1e-6;  // one row, one sample per dispatch
    options.hostCopyEveryMs = 0.0;
    options.simulateDeviceLossAtDispatch = 16 + 5;  // rows 0-3 have 2 samples, the rest 1
    GpuRenderReport report;
    const RenderResult lost = renderGpu(scene, bvh, camera, settings, options, &report);
    EXPECT_EQ(lost.stopped, StopReason::DeviceLost);
    EXPECT_EQ(report.hostCopies, 20u);
    EXPECT_EQ(lost.fewestSamples, 1u);
    EXPECT_EQ(lost.mostSamples, 2u);
    settings.samplesPerPixel = 1;
    const Image one = renderGpu(scene, bvh, camera, settings).image;
    settings.samplesPerPixel = 2;
    const Image two = renderGpu(scene, bvh, camera, settings).image;
    // Two samples added on the host (in double) and on the device (in float) round differently.
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) {
            const glm::vec3 expected = (y < 4 ? two : one).at(x, y);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(lost.image.at(x, y)[c], expected[c], 1e-6f * (1.0f + expected[c]))
                    << x << ", " << y;
        }
    }
}

TEST_F(Gpu, FiveMillionTrianglesRender) {
    // 5M triangles: 240 MB of triangles and 320 MB of nodes, beyond lavapipe's 128 MiB storage-buffer
    // range, within its 128M texels of texel-buffer range; buffer device addresses have no limit.
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
    // The device's own way (texels on lavapipe), then device addresses, which have no limit.
    for (const SceneAccess access : {SceneAccess::Auto, SceneAccess::Addresses}) {
        GpuRenderOptions options;
        options.sceneAccess = access;
        GpuRenderReport report;
        const RenderResult result =
            renderGpu(scene, bvh, frameBounds(scene.bounds, 1.0), settings, options, &report);
        EXPECT_GT(report.deviceMemoryBytes, 128ull << 20);
        if (context().properties().limits.maxStorageBufferRange < (300u << 20)) {
            EXPECT_NE(report.sceneAccess, SceneAccess::Storage) << "beyond the storage-buffer range";
        }
        // The sphere faces the light and the camera head on (white, F0 = 0.04, roughness 1): the base keeps
        // 1 - F0 of the light, the matte specular lobe adds F0 D G2 / 4 = F0 / (4 pi), so the centre shows
        // (rho (1 - F0) + F0 / 4) / pi * I / d^2 with d = 4.
        const glm::vec3 centre = result.image.at(8, 8);
        EXPECT_NEAR(centre.x, (0.96 + 0.01) / M_PI * 25.0 / 16.0, 0.005)
            << sceneAccessName(report.sceneAccess);
    }
}

}  // namespace
}  // namespace vkrt
