// Analytic scenes with known answers, on the GPU and the CPU reference alike: a white furnace that never
// gains energy, a moving square's streak against velocity times shutter (two triangles, or a box shape
// animated in a glTF file), an emissive box shape lighting a floor as its triangles do, a floor under a lamp
// far larger than its height, a dim lamp beside one far brighter, and a sphere's silhouette against its
// analytic area.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "cpu/reference_renderer.h"
#include "gpu/scene_features.h"
#include "punctual_light.h"
#include "scene/gltf_loader.h"
#include "scene/light_table.h"
#include "scene/scene_builder.h"
#include "scene/shading_inputs.h"
#include "shape_geometry.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/temporary_folder.h"
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

// An emitting box of half-size 0.1 (VKRT_shape) whose translation along x a glTF animation moves through
// `keys` (time in the shutter [0, 1], x), LINEAR, written as a file and loaded.
Scene movingBoxScene(const std::vector<std::pair<float, float>>& keys, const std::string& name) {
    std::vector<float> data;
    for (const auto& key : keys) data.push_back(key.first);
    for (const auto& key : keys) data.insert(data.end(), {key.second, 0.0f, 0.0f});
    const std::filesystem::path folder = test::temporaryFolder();
    std::ofstream(folder / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * 4));
    const size_t count = keys.size();
    const nlohmann::json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"VKRT_shape"}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}, {"extras", {{"shutter", {0.0, 1.0}}}}}}},
        {"nodes",
         {{{"name", "moving box"},
           {"translation", {keys.front().second, 0.0, 0.0}},
           {"scale", {0.1, 0.1, 0.1}},
           {"extensions", {{"VKRT_shape", {{"shape", "box"}, {"material", 0}}}}}}}},
        {"materials",
         {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}}},
           {"emissiveFactor", {1.0, 1.0, 1.0}}}}},
        {"buffers", {{{"uri", name + ".bin"}, {"byteLength", data.size() * 4}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", count * 4}},
          {{"buffer", 0}, {"byteOffset", count * 4}, {"byteLength", count * 12}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", count},
           {"type", "SCALAR"},
           {"min", {keys.front().first}},
           {"max", {keys.back().first}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}}}},
        {"animations",
         {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
           {"samplers", {{{"input", 0}, {"output", 1}, {"interpolation", "LINEAR"}}}}}}},
    };
    const std::filesystem::path file = folder / (name + ".gltf");
    std::ofstream(file) << gltf.dump(1);
    return loadGltf(file.string());
}

// A smooth sphere (vertex normals radial) turning a quarter about its vertical axis during the shutter, lit
// by a sun from near the camera: each moving triangle turns its vertex normals and tangents (given at the
// opening) with its face, so the sphere looks as it does standing still, plain and under a normal texture
// that tilts every normal 31 degrees towards its tangent (eastwards). Turned by the smallest rotation of the
// face's normal, which leaves out the face's turn about it, the normal-mapped sphere was off by 0.17 of 0.64;
// normals left as they were at the opening would turn the lit side. Both devices, against each other and the
// still sphere.
TEST_F(Gpu, SmoothNormalsAndNormalMapsTurnWithAMovingMesh) {
    for (const bool normalMap : {false, true}) {
        SCOPED_TRACE(normalMap ? "normal map" : "smooth normals");
        Scene still;
        Material white;
        white.metallic = 0.0f;
        white.specularFactor = 0.0f;  // Lambertian
        if (normalMap) {
            still.textures.push_back(test::textureOf(1, 1, {0xffff80ccu}));  // tangent space (0.6, 0, 1)
            white.normalTexture.texture = 0;
        }
        still.materials.push_back(white);
        test::addUvSphereMesh(still, 48, 96, 0, normalMap);
        // From near the camera: the shadow terminator, where a tilted normal's light ends abruptly and the
        // turning facets move it, lies outside the part of the disk compared.
        PunctualLight sun;
        sun.type = LightType::Directional;
        sun.direction = glm::normalize(glm::vec3(-0.3f, -0.2f, -1.0f));
        sun.intensity = 2.0f;
        still.lights.push_back(sun);
        Scene turning = still;
        constexpr int kSegments = 8;
        turning.motionSegments = kSegments;
        for (const Triangle& t : still.triangles) {
            for (int k = 1; k <= kSegments; ++k) {
                const glm::mat3 turn(
                    glm::rotate(glm::mat4(1.0f), 1.5707963f * k / kSegments, glm::vec3(0.0f, 1.0f, 0.0f)));
                turning.trianglePoses.push_back({turn * t.v0, turn * t.v1, turn * t.v2, t.material});
            }
        }
        finalizeScene(still);
        finalizeScene(turning);
        RenderSettings settings;
        settings.integrator = Integrator::Whitted;
        settings.width = settings.height = 32;
        settings.samplesPerPixel = 16;
        settings.ambient = glm::dvec3(0.0);
        const auto [stillGpu, stillCpu] = test::renderGpuAndCpu(
            context(), still, bvhFor(still), test::sphereCamera(), settings, test::shaderCacheDir());
        const auto [gpu, cpu] = test::renderGpuAndCpu(context(), turning, bvhFor(turning),
                                                      test::sphereCamera(), settings, test::shaderCacheDir());
        for (const auto& [moving, standing, device] : {std::tuple{&gpu.image, &stillGpu.image, "gpu"},
                                                       std::tuple{&cpu.image, &stillCpu.image, "cpu"}}) {
            // Inside the disk (away from the silhouette, where the turning facets cover pixels differently):
            // the same radiance within 1% of the brightest.
            double worst = 0.0, brightest = 0.0;
            for (int y = 0; y < settings.height; ++y) {
                for (int x = 0; x < settings.width; ++x) {
                    const double u = 2.0 * (x + 0.5) / settings.width - 1.0,
                                 v = 2.0 * (y + 0.5) / settings.height - 1.0;
                    if (u * u + v * v > 0.8 * 0.8) continue;
                    worst = std::max(
                        worst, static_cast<double>(std::abs(moving->at(x, y).x - standing->at(x, y).x)));
                    brightest = std::max(brightest, static_cast<double>(standing->at(x, y).x));
                }
            }
            EXPECT_GT(brightest, 0.3) << device;
            EXPECT_LT(worst, 0.01 * brightest) << device;
        }
        test::expectMatchesReference(gpu.image, cpu.image,
                                     normalMap ? "normal-map-turning" : "smooth-normals-turning");
    }
}

// An emitting square of side 0.2 moving 0.6 along x during the shutter, seen from straight ahead: its streak
// is side + velocity x shutter = 0.8 long, and where the square covers a point for a third of the shutter
// the streak's plateau is a third of its radiance. The square is two triangles with poses, or a box shape
// (VKRT_shape) animated in a glTF file; the box also moves unevenly (fast, then slow, several motion
// segments), where only the streak's integral is known: the box's width, whatever the motion. The GPU's
// streak is the CPU's column for column, and the box's is the triangles'.
TEST_F(Gpu, MotionBlurStreakIsVelocityTimesShutter) {
    Scene triangles;
    Material lamp;
    lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    lamp.emission = glm::vec3(1.0f);
    triangles.materials.push_back(lamp);
    addFlatQuad(triangles, {-0.5f, -0.1f, 0.0f}, {-0.3f, -0.1f, 0.0f}, {-0.3f, 0.1f, 0.0f},
                {-0.5f, 0.1f, 0.0f}, 0);
    for (const Triangle& t : triangles.triangles) {
        const glm::vec3 shift(0.6f, 0.0f, 0.0f);
        triangles.trianglePoses.push_back(
            {t.v0 + 0.5f * shift, t.v1 + 0.5f * shift, t.v2 + 0.5f * shift, t.material});
        triangles.trianglePoses.push_back({t.v0 + shift, t.v1 + shift, t.v2 + shift, t.material});
    }
    triangles.motionSegments = 2;
    finalizeScene(triangles);
    const Scene box = movingBoxScene({{0.0f, -0.4f}, {1.0f, 0.2f}}, "linear");
    ASSERT_EQ(box.solids.size(), 1u);
    ASSERT_GE(box.motionSegments, 1);
    const Scene uneven = movingBoxScene({{0.0f, -0.4f}, {0.3f, 0.1f}, {1.0f, 0.2f}}, "uneven");
    ASSERT_GT(uneven.motionSegments, 1);

    RenderSettings settings;
    settings.width = 160;
    settings.height = 16;
    settings.samplesPerPixel = 256;
    settings.ambient = glm::dvec3(0.0);
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.xmag = 1.0;
    camera.ymag = 0.1;
    const double pixel = 2.0 / settings.width;
    // Column means over the image's height (the square covers it all).
    auto columns = [&](const Image& image) {
        std::vector<double> column(settings.width, 0.0);
        for (int x = 0; x < settings.width; ++x) {
            for (int y = 0; y < settings.height; ++y) column[x] += image.at(x, y).x / settings.height;
        }
        return column;
    };
    std::vector<double> triangleColumns;
    for (const Scene* scene : {static_cast<const Scene*>(&triangles), &box, &uneven}) {
        const std::string name = scene == &triangles ? "triangles"
                                 : scene == &box     ? "box shape"
                                                     : "uneven box shape";
        const FlatBvh bvh = bvhFor(*scene);
        camera.position = glm::dvec3(0.0, 0.0, 2.0) - scene->origin;  // the loader re-centres the files
        const Image gpu = renderGpu(*scene, bvh, camera, settings).image;
        const Image cpu = ReferenceRenderer(*scene, bvh, camera, settings).render().image;
        const std::vector<double> gpuColumns = columns(gpu), cpuColumns = columns(cpu);
        for (const std::vector<double>* column : {&gpuColumns, &cpuColumns}) {
            const std::string which = name + (column == &gpuColumns ? ", gpu" : ", cpu");
            double total = 0.0;
            for (double c : *column) total += c * pixel;
            EXPECT_NEAR(total, 0.2, 0.002) << which;  // the square's width, whatever the motion
            if (scene == &uneven) continue;
            // Streak length: the span of columns that saw any light.
            int first = -1, last = -1;
            double plateau = 0.0;
            int plateauCount = 0;
            for (int x = 0; x < settings.width; ++x) {
                const double centre = -1.0 + (x + 0.5) * pixel;
                if ((*column)[x] > 1e-3) {
                    if (first < 0) first = x;
                    last = x;
                }
                if (centre > -0.25 && centre < 0.05) {  // fully inside the plateau [-0.3, 0.1]
                    plateau += (*column)[x];
                    ++plateauCount;
                }
            }
            const double length = (last - first + 1) * pixel;
            EXPECT_NEAR(length, 0.8, 1.5 * pixel) << which;
            EXPECT_NEAR(plateau / plateauCount, 1.0 / 3.0, 0.01) << which;
        }
        // The same samples on both devices (the same seed): column for column, up to a few samples that land
        // on the other side of an edge (one of the 4,096 a column holds is 2.4e-4).
        double worst = 0.0, worstAgainstTriangles = 0.0;
        for (int x = 0; x < settings.width; ++x) {
            worst = std::max(worst, std::abs(gpuColumns[x] - cpuColumns[x]));
            if (!triangleColumns.empty())
                worstAgainstTriangles =
                    std::max(worstAgainstTriangles, std::abs(gpuColumns[x] - triangleColumns[x]));
        }
        std::printf("%s: GPU against CPU, worst column off by %.3g; against the triangles' %.3g\n",
                    name.c_str(), worst, worstAgainstTriangles);
        EXPECT_LE(worst, 2e-3) << name;
        if (scene == &triangles) triangleColumns = gpuColumns;
        if (scene == &box) {
            EXPECT_LE(worstAgainstTriangles, 2e-3) << name;
        }
    }
}

// A floor lit by an emissive box, the box once a shape (VKRT_shape: sampled part by part, with Nanson's
// density) and once twelve triangles at the same corners: the same light. The box is a thin slab turned about
// a tilted axis, so its faces differ in area and in how they see the floor; the camera looks straight down
// from between the floor and the light (which it does not see), and the mean over the image is the floor's
// mean radiance, within 2% (the ratio varies by about 0.25% from seed to seed: 65,536 samples a render), path
// and Whitted, GPU and CPU.
// A Lambertian floor of albedo 0.8, 6 x 6 at y = 0 facing up (material 0), and a black lamp material of
// radiance `radiance` (material 1) for the lamp the test adds.
Scene litFloor(float radiance) {
    Scene scene;
    scene.materials.push_back(test::lambertian(0.8f));
    Material lamp;
    lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    lamp.emission = glm::vec3(radiance);
    scene.materials.push_back(lamp);
    addFlatQuad(scene, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, {-3, 0, -3}, 0);
    return scene;
}

// A camera at `height` above the origin looking straight down (-Y), -Z up the image, of vertical field `yfov`.
Camera lookingDown(double height, double yfov) {
    Camera camera;
    camera.position = {0.0, height, 0.0};
    camera.forward = {0.0, -1.0, 0.0};
    camera.up = {0.0, 0.0, -1.0};
    camera.right = glm::cross(camera.forward, camera.up);
    camera.yfov = yfov;
    return camera;
}

TEST_F(Gpu, EmissiveBoxShapeLightsTheFloorAsItsTrianglesDo) {
    const glm::dmat4 map =
        glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 1.3, -0.1)) *
        glm::rotate(glm::dmat4(1.0), glm::radians(35.0), glm::normalize(glm::dvec3(1.0, 0.4, 0.3))) *
        glm::scale(glm::dmat4(1.0), glm::dvec3(0.5, 0.08, 0.3));
    auto build = [&](bool shape) {
        Scene scene = litFloor(4.0f);
        if (shape) {
            std::array<uint32_t, 8> alone{};
            alone[0] = 2u;  // inside exactly when inside shape 0
            addSolid(scene, {makeShape(VKRT_SHAPE_BOX, 1, map)}, alone);
        } else {
            // The faces of [-1, 1]^3 mapped, counter-clockwise seen from outside.
            for (int a = 0; a < 3; ++a) {
                for (const double side : {-1.0, 1.0}) {
                    glm::vec3 corner[4];
                    const double uv[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
                    for (int k = 0; k < 4; ++k) {
                        glm::dvec3 p(0.0);
                        p[a] = side;
                        p[(a + 1) % 3] = uv[k][0];
                        p[(a + 2) % 3] = side > 0 ? uv[k][1] : -uv[k][1];
                        corner[k] = glm::vec3(map * glm::dvec4(p, 1.0));
                    }
                    addFlatQuad(scene, corner[0], corner[1], corner[2], corner[3], 1);
                }
            }
        }
        finalizeScene(scene);
        return scene;
    };
    const Scene shape = build(true), triangles = build(false);
    ASSERT_EQ(shape.emissiveShapes.size(), 1u);
    ASSERT_EQ(triangles.emissiveTriangles.size(), 12u);
    const Camera camera = lookingDown(0.6, 1.2);
    for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        RenderSettings settings;
        settings.integrator = integrator;
        settings.width = settings.height = 32;
        settings.samplesPerPixel = 64;
        settings.ambient = glm::dvec3(0.0);
        settings.background = glm::dvec3(0.0);
        double means[2][2];  // [shape or triangles][GPU or CPU]
        for (const Scene* scene : {&shape, &triangles}) {
            const test::RenderPair pair = test::renderGpuAndCpu(context(), *scene, bvhFor(*scene), camera,
                                                                settings, test::shaderCacheDir());
            for (const RenderResult* result : {&pair.gpu, &pair.cpu}) {
                EXPECT_EQ(result->rays.nonFiniteSamples, 0u);
                double sum = 0.0;
                for (const glm::vec3& p : result->image.pixels) sum += p.x;
                means[scene == &triangles][result == &pair.cpu] =
                    sum / static_cast<double>(result->image.pixels.size());
            }
        }
        for (int device = 0; device < 2; ++device) {
            const std::string which =
                std::string(integratorName(integrator)) + (device == 0 ? ", gpu" : ", cpu");
            std::printf(
                "%s: the floor's mean radiance %.5f under the shape, %.5f under the triangles (ratio %.4f)\n",
                which.c_str(), means[0][device], means[1][device], means[0][device] / means[1][device]);
            EXPECT_GT(means[1][device], 0.05) << which << ": the floor must be lit";
            EXPECT_NEAR(means[0][device] / means[1][device], 1.0, 0.02) << which;
        }
    }
}

// A lamp far larger than its height over a floor, as a sky quad or a ceiling panel is: Whitted's diffuse
// floor sees it through light samples alone. Sampled by area, nearly every point lay thousands of units away,
// and the floor was a few fireflies on black (a review: at 64 spp); sampled by the solid angle each triangle
// covers, the only variance left is the cosine's. Against the closed form (Howell's B-3, four corner
// rectangles), pixel by pixel.
TEST_F(Gpu, FloorUnderALampFarLargerThanItsHeightIsSmooth) {
    Scene scene = litFloor(2.0f);
    const float half = 5000.0f, height = 5.0f;  // facing down
    addFlatQuad(scene, {-half, height, -half}, {half, height, -half}, {half, height, half},
                {-half, height, half}, 1);
    finalizeScene(scene);
    ASSERT_EQ(scene.emissiveTriangles.size(), 2u);
    EXPECT_TRUE(detectFeatures(scene).solidAngleTriangles);
    {
        // A lamp 1 across at the same height is small beside the scene: sampled by area, its sampler left
        // out.
        Scene small = litFloor(2.0f);
        addFlatQuad(small, {-0.5f, height, -0.5f}, {0.5f, height, -0.5f}, {0.5f, height, 0.5f},
                    {-0.5f, height, 0.5f}, 1);
        finalizeScene(small);
        EXPECT_FALSE(detectFeatures(small).solidAngleTriangles);
        EXPECT_FALSE(buildLightTable(small).solidAngleTriangles);
    }
    const double x = half / height,
                 formFactor = 4.0 * (x / std::sqrt(1 + x * x) * std::atan(x / std::sqrt(1 + x * x)) / M_PI);
    const double expected = 0.8 * 2.0 * formFactor;
    const Camera camera = lookingDown(2.0, 0.8);
    // Whitted's light samples alone; paths' weighed against the floor's own rays by MIS, and without MIS (the
    // lamp is black and the floor flat: the floor's light is all direct).
    for (const auto& [integrator, mis] :
         {std::pair{Integrator::Whitted, true}, std::pair{Integrator::Path, true},
          std::pair{Integrator::Path, false}}) {
        RenderSettings settings;
        settings.integrator = integrator;
        settings.multipleImportanceSampling = mis;
        settings.width = settings.height = 24;
        settings.samplesPerPixel = 64;
        settings.ambient = glm::dvec3(0.0);
        settings.background = glm::dvec3(0.0);
        const test::RenderPair pair =
            test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
        for (const RenderResult* result : {&pair.gpu, &pair.cpu}) {
            const std::string which = std::string(integratorName(integrator)) + (mis ? "" : " without MIS") +
                                      (result == &pair.gpu ? ", gpu" : ", cpu");
            EXPECT_EQ(result->rays.nonFiniteSamples, 0u) << which;
            double sum = 0.0, sumSquares = 0.0, lowest = 1e30, highest = 0.0;
            for (const glm::vec3& p : result->image.pixels) {
                sum += p.x;
                sumSquares += double(p.x) * p.x;
                lowest = std::min(lowest, double(p.x));
                highest = std::max(highest, double(p.x));
            }
            const double n = static_cast<double>(result->image.pixels.size());
            const double mean = sum / n, spread = std::sqrt(std::max(0.0, sumSquares / n - mean * mean));
            std::printf("%s: floor %.5f (closed form %.5f), pixels %.5f to %.5f, deviation %.5f\n",
                        which.c_str(), mean, expected, lowest, highest, spread);
            EXPECT_NEAR(mean, expected, 0.01 * expected) << which;
            EXPECT_LT(spread, 0.1 * expected) << which;
            EXPECT_GT(lowest, 0.7 * expected) << which;
            EXPECT_LT(highest, 1.3 * expected) << which;
        }
    }
}

TEST(LightTable, PicksAreExactOnTheGridOfTwoRandomNumbers) {
    // Three lamps of power 1, 1e-9 and 3 (triangles of one size, radiance 1, 1e-9, 3): each is picked with
    // nine tenths of its share of the power plus a tenth of a third, on the grid of 2^-48 that two 24-bit
    // random numbers read as one, so the stated probability is the one the search gives.
    Scene scene;
    for (float radiance : {1.0f, 1e-9f, 3.0f}) {
        Material lamp;
        lamp.emission = glm::vec3(radiance);
        scene.materials.push_back(lamp);
        const float x = 2.0f * static_cast<float>(scene.materials.size());
        addFlatTriangle(scene, {x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0},
                        static_cast<uint32_t>(scene.materials.size() - 1));
    }
    finalizeScene(scene);
    const LightTable table = buildLightTable(scene);
    ASSERT_EQ(table.primitives.size(), 3u);
    const uint64_t grid = LightTable::kLightSteps;
    EXPECT_EQ(table.steps.back(), grid);
    for (size_t i = 0; i < 3; ++i) {
        const uint64_t first = i > 0 ? table.steps[i - 1] : 0, own = table.steps[i] - first;
        EXPECT_EQ(table.pick[i], static_cast<double>(own) / static_cast<double>(grid));
        const double power = std::array<double, 3>{1.0, 1e-9, 3.0}[i] / (4.0 + 1e-9);
        EXPECT_NEAR(table.pick[i], 0.9 * power + 0.1 / 3.0, 2.0 / static_cast<double>(grid)) << i;
        EXPECT_EQ(table.find(first), i);
        EXPECT_EQ(table.find(table.steps[i] - 1), i);
    }
}

// An orthographic camera at `position` looking straight down (-Y), -Z up the image, seeing a square of
// half-side `half`.
Camera orthographicDown(glm::dvec3 position, double half) {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = position;
    camera.forward = {0.0, -1.0, 0.0};
    camera.up = {0.0, 0.0, -1.0};
    camera.right = glm::cross(camera.forward, camera.up);
    camera.xmag = camera.ymag = half;
    return camera;
}

// `scene` seen by `camera` with both integrators on both devices (`base`'s size, samples and depth; no
// ambient or background light): each image's mean green within `tolerance` of `expected`, every sample
// finite, and at most `shadowRaysPerSample` shadow rays a sample on the CPU.
void expectMeanGreen(const VulkanContext& context, const Scene& scene, const Camera& camera,
                     RenderSettings base, double expected, double tolerance,
                     double shadowRaysPerSample = 1e30) {
    for (Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        RenderSettings settings = base;
        settings.integrator = integrator;
        settings.ambient = glm::dvec3(0.0);
        settings.background = glm::dvec3(0.0);
        const test::RenderPair pair =
            test::renderGpuAndCpu(context, scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
        const double samples =
            static_cast<double>(settings.width) * settings.height * settings.samplesPerPixel;
        EXPECT_LE(static_cast<double>(pair.cpu.rays.shadow), shadowRaysPerSample * samples);
        for (const RenderResult* result : {&pair.gpu, &pair.cpu}) {
            const std::string which =
                std::string(integratorName(integrator)) + (result == &pair.gpu ? ", gpu" : ", cpu");
            double sum = 0.0;
            for (const glm::vec3& p : result->image.pixels) sum += p.y;
            const double mean = sum / static_cast<double>(result->image.pixels.size());
            std::printf("%s: mean %.6f (closed form %.6f)\n", which.c_str(), mean, expected);
            EXPECT_NEAR(mean, expected, tolerance * expected) << which;
            EXPECT_EQ(result->rays.nonFiniteSamples, 0u) << which;
        }
    }
}

// Up to VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO punctual lights, every shading point takes light from each (no
// table); beyond, each light sample picks one from a table on the same grid and with the same shares as the
// lamps'.
TEST(LightTable, PunctualLightsArePickedOnlyBeyondTheLimit) {
    Scene scene;
    for (uint32_t i = 0; i < VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO; ++i) {
        PunctualLight light;
        light.intensity = i == 0 ? 0.0f : 1.0f;  // one dark light: picked by the uniform share alone
        scene.lights.push_back(light);
    }
    EXPECT_TRUE(buildPunctualLightTable(scene).empty());
    scene.lights.push_back(PunctualLight{});
    const PunctualLightTable table = buildPunctualLightTable(scene);
    const size_t count = scene.lights.size();
    ASSERT_EQ(table.steps.size(), count);
    EXPECT_EQ(table.steps.back(), LightTable::kLightSteps);
    EXPECT_NEAR(table.pick[0], 0.1 / count, 1e-12);
    EXPECT_NEAR(table.pick[1], 0.9 / (count - 1) + 0.1 / count, 1e-12);
}

TEST_F(Gpu, DimLampBesideOneFarBrighterLightsTheFloor) {
    // A lamp sphere of radius r and radiance 1 at height h over the floor, and one 1e14 times as powerful
    // under it (the floor hides it from the top). Where the floor is lit by the dim lamp alone, at distance D
    // from its centre, it shows albedo L (r / D)^2 (h / D). Picked by power alone the dim lamp got 1e-14 of
    // the light samples, and Whitted, which reaches it by light samples only, left the floor black on both
    // devices; a tenth of the samples now pick a light uniformly. Paths weigh their bounce rays that meet the
    // lamp by the same probability (MIS): a pick that differed from the table's would show in their mean.
    const double albedo = 0.8, r = 0.05, h = 1.0;
    Scene scene = litFloor(1.0f);
    scene.spheres.push_back({glm::vec3(0.0f, static_cast<float>(h), 0.0f), static_cast<float>(r), 1});
    Material sun;
    sun.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    sun.emission = glm::vec3(1e12f);
    scene.materials.push_back(sun);
    scene.spheres.push_back({glm::vec3(0.0f, -5.0f, 0.0f), 0.5f, 2});
    finalizeScene(scene);
    const LightTable lights = buildLightTable(scene);
    ASSERT_EQ(lights.primitives.size(), 2u);
    // A patch of the floor 0.01 across, 0.3 from the lamp's foot, seen from straight above.
    const Camera camera = orthographicDown({0.3, 2.0, 0.0}, 0.005);
    const int size = 32;
    double expected = 0.0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const double px = 0.3 + 0.005 * (2.0 * (x + 0.5) / size - 1.0),
                         pz = 0.005 * (2.0 * (y + 0.5) / size - 1.0);
            const double d = std::sqrt(px * px + pz * pz + h * h);
            expected += albedo * (r / d) * (r / d) * (h / d) / (size * size);
        }
    }
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = 256;
    expectMeanGreen(context(), scene, camera, settings, expected, 0.04);
}

// A floor under 200 point lights (more than VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO) of intensities from 1e-3 to 1e3
// candela, one a spot and one directional: each light sample picks one light, nine tenths by power and a
// tenth uniformly, from the table (host/scene/light_table.h), and the floor shows albedo / pi times the sum
// of the lights' irradiance. Every light took a shadow ray at every hit: a scene of 10,000 ran out of
// lavapipe's loop budget (exit 1, nothing written) and took the CPU 5.3 s for 32 x 32 pixels at 8 spp, now
// 0.3 s.
TEST_F(Gpu, ManyPunctualLightsArePickedByPowerAndLightTheFloorAsTheirSum) {
    Scene scene = litFloor(0.0f);
    uint32_t state = 12345u;
    auto uniform = [&state] {
        state = state * 1664525u + 1013904223u;
        return static_cast<double>(state >> 8) / 16777216.0;
    };
    for (int i = 0; i < 200; ++i) {
        PunctualLight light;
        light.position = {4.0 * uniform() - 2.0, 0.5 + 2.0 * uniform(), 4.0 * uniform() - 2.0};
        light.intensity = static_cast<float>(std::pow(10.0, 6.0 * uniform() - 3.0));
        light.color = glm::vec3(1.0f, 0.8f, 0.6f);
        if (i == 7) {
            light.type = LightType::Spot;
            light.direction = glm::normalize(glm::dvec3(0.1, -1.0, 0.0));
            light.innerConeAngle = 0.3f;
            light.outerConeAngle = 0.6f;
        }
        if (i == 11) {
            light.type = LightType::Directional;
            light.direction = glm::normalize(glm::dvec3(0.3, -1.0, 0.2));
            light.intensity = 2.0f;
        }
        scene.lights.push_back(light);
    }
    finalizeScene(scene);
    const PunctualLightTable table = buildPunctualLightTable(scene);
    ASSERT_EQ(table.pick.size(), 200u);
    EXPECT_EQ(table.steps.back(), LightTable::kLightSteps);
    EXPECT_EQ(table.find(table.steps[6]), 7u);
    // A patch of the floor 0.02 across at the origin, seen from straight above.
    const Camera camera = orthographicDown({0.0, 3.0, 0.0}, 0.01);
    const int size = 16;
    const shading::PunctualLightParams spot = punctualLightParams(scene.lights[7]);
    double expected = 0.0;  // the green channel's closed form, averaged over the pixels' centres
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const glm::dvec3 point(0.01 * (2.0 * (x + 0.5) / size - 1.0), 0.0,
                                   0.01 * (2.0 * (y + 0.5) / size - 1.0));
            for (const PunctualLight& light : scene.lights) {
                const shading::LightArrival arrival = shading::arriveFrom(punctualLightParams(light), point);
                expected +=
                    0.8 / M_PI * arrival.irradiance.y * std::max(0.0, arrival.toLight.y) / (size * size);
            }
        }
    }
    ASSERT_GT(shading::arriveFrom(spot, glm::dvec3(0.0)).irradiance.y, 0.0) << "the spot lights the patch";
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = 256;
    settings.maxDepth = 0;  // the lights' direct light alone
    expectMeanGreen(context(), scene, camera, settings, expected, 0.02, 1.0);  // a light a sample, not 200
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
