// The CPU reference renderer against closed forms: a Lambertian plane under punctual lights, irradiance
// from a square area light, Beer's law through a slab, and a Cornell box a person would recognise.
#include <cmath>
#include <limits>
#include <utility>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "app/render_policy.h"
#include "bvh/triangle_bvh.h"
#include "cpu/reference_renderer.h"
#include "image/image_metrics.h"
#include "punctual_light.h"
#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"
#include "scene/shading_inputs.h"
#include "shape_geometry.h"
#include "support/gltf_document.h"
#include "support/render_both.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;

Material lambert(glm::vec3 albedo) {
    Material m;
    m.baseColor = glm::vec4(albedo, 1.0f);
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.ior = 1.0f;  // index 1: no specular reflectance at all, so the surface is exactly Lambertian
    return m;
}

RenderSettings quietSettings() {
    RenderSettings settings;
    settings.ambient = glm::dvec3(0.0);
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 1;
    return settings;
}

// A 20 x 20 Lambertian floor at z = 0 facing +z.
Scene floorScene(float albedo) {
    Scene scene;
    scene.materials.push_back(lambert(glm::vec3(albedo)));
    addFlatQuad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
    return scene;
}

glm::dvec3 radianceDown(const ReferenceRenderer& renderer, double x, double y) {
    RayCounters counters;
    return renderer.radiance({{x, y, 5.0}, {0.0, 0.0, -1.0}}, 0, 0, counters);
}

// Both renderers address the packed texels (every texture's levels, one after another) with 32 bits: textures
// holding more are refused by name before anything is packed, where the offsets wrapped and a texture read
// another's texels. The textures here are described, never packed: their level 0 is one texel, and their mip
// chains count from their size (1.43e9 texels each). Each has texels of its own (textures that share theirs
// are packed once).
TEST(ShadingInputs, TexelsBeyond32BitAddressesAreRefused) {
    Scene scene;
    std::vector<Texture> huge(4);
    for (Texture& texture : huge) {
        texture.width = texture.height = 65535;
        texture.rgba = std::make_shared<const std::vector<uint8_t>>(4, 0xff);
    }
    scene.textures.assign(huge.begin(), huge.begin() + 2);
    EXPECT_EQ(describeTextures(scene).size(), 2u);
    scene.textures = huge;
    try {
        describeTextures(scene);
        ADD_FAILURE() << "described textures past 2^32 texels";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("vkrt addresses at most 2^32 - 1"), std::string::npos)
            << e.what();
    }
}

TEST(PathContinuations, SubnormalWeightsNeverTakeAContinuationThatIsNotThere) {
    // A smooth sheen over a black base can weigh its cosine-sampled continuation 1e-320 in double precision
    // (0 in float): u, a random number times that total, rounded up to the total's end for about half the
    // samples, and the reflection, which did not exist, was taken with probability 0 (the CPU's samples NaN;
    // a review counted 2 to 4 in 4M samples of a sheen sphere). The one continuation there is must be taken,
    // with its weight.
    shading::ShadingContext context{};
    context.paths = true;
    shading::ShadedHit shaded{};
    shaded.indexHere = shaded.indexBeyond = 1.0;
    shaded.scatters = true;
    shaded.scatterWeight = glm::dvec3(std::numeric_limits<double>::denorm_min());
    shaded.scattered = shading::rayState(glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0), shaded.scatterWeight, 1u,
                                         1, VKRT_NO_PRIMITIVE, 0.0, shading::emptyMedia());
    const shading::RayState ray =
        shading::rayState(glm::dvec3(0.0), glm::dvec3(0.0, 0.0, -1.0), glm::dvec3(1.0), 0u, 0,
                          VKRT_NO_PRIMITIVE, 0.0, shading::emptyMedia());
    for (uint32_t sample = 0; sample < 256; ++sample) {
        context.pairRoot = vkrtPairRoot(vkrtPixelStream(0u, sample % 7u));
        context.sampleIndex = sample;
        shading::RayState next;
        ASSERT_TRUE(shading::continuePath(context, ray, shaded, next)) << sample;  // depth 1: no roulette
        EXPECT_EQ(next.direction, glm::dvec3(0.0, 0.0, 1.0)) << sample;
        EXPECT_EQ(next.throughput, shaded.scatterWeight) << sample;
    }
}

TEST(ReferenceRenderer, LambertianPlaneUnderPointLightMatchesClosedForm) {
    Scene scene = floorScene(0.625f);  // binary fractions keep float storage exact
    PunctualLight light;
    light.type = LightType::Point;
    light.position = {0.3, -0.2, 1.5};
    light.intensity = 7.0f;
    light.color = {1.0f, 0.5f, 0.25f};
    scene.lights.push_back(light);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), quietSettings());
    for (double x : {-3.0, -0.5, 0.3, 1.0, 4.0}) {
        for (double y : {-2.0, 0.0, 2.5}) {
            // L = rho / pi * I cos(theta) / d^2, with cos(theta) = h / d.
            const glm::dvec3 toLight = light.position - glm::dvec3(x, y, 0.0);
            const double d = glm::length(toLight);
            const double expected = 0.625 / M_PI * 7.0 * (1.5 / d) / (d * d);
            const glm::dvec3 L = radianceDown(renderer, x, y);
            EXPECT_NEAR(L.x, expected * 1.0, 1e-12 * expected) << x << "," << y;
            EXPECT_NEAR(L.y, expected * 0.5, 1e-12 * expected);
            EXPECT_NEAR(L.z, expected * 0.25, 1e-12 * expected);
        }
    }
}

TEST(ReferenceRenderer, SpotAndDirectionalLightsFollowTheSpec) {
    Scene scene = floorScene(1.0f);
    PunctualLight spot;
    spot.type = LightType::Spot;
    spot.position = {0.0, 0.0, 2.0};
    spot.direction = {0.0, 0.0, -1.0};
    spot.intensity = 10.0f;
    spot.innerConeAngle = 0.25f;
    spot.outerConeAngle = 0.5f;
    scene.lights.push_back(spot);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), quietSettings());
    // Inside the inner cone: full intensity; outside the outer cone: dark; between: the spec's smooth
    // falloff, squared.
    const double x0 = 2.0 * std::tan(0.1);
    const double d0 = std::hypot(x0, 2.0);
    EXPECT_NEAR(radianceDown(renderer, x0, 0).x, 10.0 / M_PI * (2.0 / d0) / (d0 * d0), 1e-12);
    EXPECT_EQ(radianceDown(renderer, 2.0 * std::tan(0.55), 0).x, 0.0);
    const double angle = 0.35, x1 = 2.0 * std::tan(angle), d1 = std::hypot(x1, 2.0);
    const double t = (std::cos(angle) - std::cos(0.5)) / (std::cos(0.25) - std::cos(0.5));
    EXPECT_NEAR(radianceDown(renderer, x1, 0).x, 10.0 / M_PI * (2.0 / d1) / (d1 * d1) * t * t, 1e-12);

    Scene sunny = floorScene(0.5f);
    PunctualLight sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::dvec3(1.0, 0.0, -1.0));
    sun.intensity = 3.0f;
    sunny.lights.push_back(sun);
    finalizeScene(sunny);
    const FlatBvh sunnyBvh = bvhFor(sunny);
    const ReferenceRenderer sunRenderer(sunny, sunnyBvh, frameBounds(sunny.bounds, 1.0), quietSettings());
    EXPECT_NEAR(radianceDown(sunRenderer, 1.0, 1.0).x, 0.5 / M_PI * 3.0 * std::sqrt(0.5), 1e-12);
}

TEST(ReferenceRenderer, PointLightRangeWindow) {
    PunctualLight light;
    light.position = {0.0, 0.0, 0.0};
    light.range = 2.0f;
    EXPECT_NEAR(shading::arriveFrom(punctualLightParams(light), {1.0, 0.0, 0.0}).irradiance.x,
                1.0 - std::pow(0.5, 4), 1e-12);
    EXPECT_EQ(shading::arriveFrom(punctualLightParams(light), {2.5, 0.0, 0.0}).irradiance.x, 0.0);
}

TEST(ReferenceRenderer, OccluderCastsAHardShadow) {
    Scene scene = floorScene(1.0f);
    addFlatQuad(scene, {-0.5f, -0.5f, 1.0f}, {0.5f, -0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}, {-0.5f, 0.5f, 1.0f}, 0);
    PunctualLight light;
    light.position = {0.0, 0.0, 3.0};
    scene.lights.push_back(light);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), quietSettings());
    // The shadow of the unit square at height 1 under a light at height 3 spans |x| < 0.75 on the floor.
    RayCounters counters;
    auto floorRadiance = [&](double x) {
        return renderer.radiance({{x, 0.0, 0.5}, {0.0, 0.0, -1.0}}, 0, 0, counters).x;
    };
    EXPECT_EQ(floorRadiance(0.7), 0.0);
    EXPECT_GT(floorRadiance(0.8), 0.0);
}

// Differential form factor from a point to a parallel rectangle of size a x b with one corner straight
// above it at height h (Howell's catalogue, configuration B-3).
double cornerFormFactor(double a, double b, double h) {
    const double x = a / h, y = b / h;
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2.0 * M_PI);
}

TEST(ReferenceRenderer, SquareAreaLightIrradianceMatchesClosedForm) {
    Scene scene = floorScene(0.8f);
    Material emitter = lambert(glm::vec3(0.0f));
    emitter.emission = glm::vec3(5.0f);
    scene.materials.push_back(emitter);
    // A 1 x 1 emitter at height 1.2 facing down (clockwise seen from above).
    const float h = 1.2f;
    addFlatQuad(scene, {-0.5f, -0.5f, h}, {-0.5f, 0.5f, h}, {0.5f, 0.5f, h}, {0.5f, -0.5f, h}, 1);
    finalizeScene(scene);
    ASSERT_EQ(scene.emissiveTriangles.size(), 2u);
    const FlatBvh bvh = bvhFor(scene);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), quietSettings());
    // Under the centre: four corner rectangles of 0.5 x 0.5. Lambertian radiance = rho * L_e * F.
    const double expected = 0.8 * 5.0 * 4.0 * cornerFormFactor(0.5, 0.5, h);
    constexpr int samples = 40000;
    double sum = 0.0, sumSquares = 0.0;
    for (int s = 0; s < samples; ++s) {
        RayCounters counters;
        const double L =
            renderer.radiance({{0.0, 0.0, 0.5}, {0.0, 0.0, -1.0}}, 17, static_cast<uint32_t>(s), counters).x;
        sum += L;
        sumSquares += L * L;
    }
    const double mean = sum / samples;
    const double standardError = std::sqrt((sumSquares / samples - mean * mean) / samples);
    EXPECT_NEAR(mean, expected, 4.0 * standardError + 1e-9) << "standard error " << standardError;
    EXPECT_LT(standardError, 0.01 * expected);  // the test is sharp enough to mean something
}

// A lamp reaching 1e9 units (the triangle (-S, 1, -S), (S, 1, -S), (S, 1, S), radiance 4, both sides
// emitting) over a Lambertian floor 1e3 across (albedo 0.5, index 1), the corners in one accessor as a file
// would give them: the floor under the lamp's long edge sees half a sky of 4, so it reads 0.5 * 4 / 2 = 1.
// Re-centred about a corner of the floor, the lamp's corners were rounded by 24 to float and the edge moved
// 34 units: the floor read 2 (a whole sky), and a camera looking up at the edge saw only lamp.
TEST(ReferenceRenderer, FloorUnderTheEdgeOfAFarReachingLampSeesHalfItsSky) {
    constexpr float S = 1e9f;
    const std::vector<float> corners = {-S,    1, -S,    S,    1, -S,    S,    1, S,  // the lamp
                                        -1e3f, 0, -1e3f, 1e3f, 0, -1e3f, 1e3f, 0, 1e3f, -1e3f, 0, 1e3f};
    test::GltfDocument d;
    const int positions = d.positions(corners);
    const int lampIndices = d.unsignedShorts({0, 1, 2}, "SCALAR");
    const int floorIndices = d.unsignedShorts({3, 5, 4, 3, 6, 5}, "SCALAR");
    d.json["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", positions}}}, {"indices", lampIndices}, {"material", 0}}}}},
        {{"primitives",
          {{{"attributes", {{"POSITION", positions}}}, {"indices", floorIndices}, {"material", 1}}}}}};
    d.json["materials"] = {
        {{"emissiveFactor", {1, 1, 1}},
         {"doubleSided", true},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}},
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}}},
         {"extensions", {{"KHR_materials_ior", {{"ior", 1.0}}}}}}};
    d.json["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior"};
    d.node({{"mesh", 0}});
    d.node({{"mesh", 1}});
    const auto file = test::temporaryFolder() / "far-lamp.gltf";
    d.write(file);
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.triangles.size(), 3u);
    // Every corner where the file puts it, exactly (the lamp is triangle 0: the first node's).
    const Triangle& lamp = scene.triangles[0];
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 stored(k == 0 ? lamp.v0 : k == 1 ? lamp.v1 : lamp.v2);
        for (int axis = 0; axis < 3; ++axis)
            EXPECT_EQ(stored[axis] + scene.origin[axis], static_cast<double>(corners[3 * k + axis]))
                << "corner " << k << " axis " << axis;
    }
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings = quietSettings();
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
    constexpr int samples = 4000;
    double sum = 0.0, sumSquares = 0.0;
    for (int s = 0; s < samples; ++s) {
        RayCounters counters;
        const double L = renderer
                             .radiance({glm::dvec3(0.0, 0.5, 0.0) - scene.origin, {0.0, -1.0, 0.0}}, 17,
                                       static_cast<uint32_t>(s), counters)
                             .x;
        sum += L;
        sumSquares += L * L;
    }
    const double mean = sum / samples;
    const double standardError = std::sqrt((sumSquares / samples - mean * mean) / samples);
    EXPECT_NEAR(mean, 1.0, 4.0 * standardError + 1e-6) << "standard error " << standardError;
    EXPECT_LT(standardError, 0.01);
}

TEST(ReferenceRenderer, SphereLightIrradianceMatchesClosedForm) {
    // A sphere of radius R and radiance L_e whose centre is at distance d from a point, in direction theta
    // from its normal, and wholly above its horizon: E = pi L_e (R / d)^2 cos(theta). Sampled by solid angle.
    Scene scene = floorScene(0.8f);
    Material emitter = lambert(glm::vec3(0.0f));
    emitter.emission = glm::vec3(3.0f);
    scene.materials.push_back(emitter);
    const double R = 0.25, h = 1.0;
    scene.spheres.push_back({{0.0f, 0.0f, static_cast<float>(h)}, static_cast<float>(R), 1});
    finalizeScene(scene);
    ASSERT_EQ(scene.emissiveSpheres.size(), 1u);
    const FlatBvh bvh = bvhFor(scene);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), quietSettings());
    for (double x : {0.0, 0.7}) {
        const double d2 = x * x + h * h, cosTheta = h / std::sqrt(d2);
        const double expected = 0.8 / M_PI * M_PI * 3.0 * R * R / d2 * cosTheta;
        constexpr int samples = 4000;
        double sum = 0.0, sumSquares = 0.0;
        for (int s = 0; s < samples; ++s) {
            RayCounters counters;
            const double L =
                renderer.radiance({{x, 0.0, 0.1}, {0.0, 0.0, -1.0}}, 3, static_cast<uint32_t>(s), counters).x;
            sum += L;
            sumSquares += L * L;
        }
        const double mean = sum / samples;
        const double standardError = std::sqrt(std::max(0.0, sumSquares / samples - mean * mean) / samples);
        EXPECT_NEAR(mean, expected, 4.0 * standardError + 1e-9 * expected) << "x = " << x;
        EXPECT_LT(standardError, 0.01 * expected);
    }
}

// A shiny metal floor reflecting a small, bright sphere light: the radiance seen in the mirror direction,
// per sample, with and without multiple importance sampling.
struct Estimate {
    double mean, variance;
};
Estimate glossyHighlight(float roughness, bool mis) {
    Scene scene;
    Material metal = lambert(glm::vec3(1.0f));
    metal.metallic = 1.0f;
    metal.roughness = roughness;
    scene.materials.push_back(metal);
    addFlatQuad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
    Material lamp = lambert(glm::vec3(0.0f));
    lamp.emission = glm::vec3(100.0f);
    scene.materials.push_back(lamp);
    scene.spheres.push_back({{1.0f, 0.0f, 1.0f}, 0.05f, 1});
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings = quietSettings();
    settings.maxDepth = 1;
    settings.multipleImportanceSampling = mis;
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
    const glm::dvec3 direction = glm::normalize(glm::dvec3(1.0, 0.0, -1.0));
    constexpr int samples = 20000;
    double sum = 0.0, sumSquares = 0.0;
    for (int s = 0; s < samples; ++s) {
        RayCounters counters;
        const double L =
            renderer.radiance({{-1.0, 0.0, 1.0}, direction}, 5, static_cast<uint32_t>(s), counters).x;
        sum += L;
        sumSquares += L * L;
    }
    const double mean = sum / samples;
    return {mean, std::max(0.0, sumSquares / samples - mean * mean)};
}

TEST(ReferenceRenderer, MultipleImportanceSamplingKeepsTheMeanAndCutsTheNoise) {
    for (float roughness : {0.05f, 0.3f}) {
        const Estimate with = glossyHighlight(roughness, true), without = glossyHighlight(roughness, false);
        const double standardError = std::sqrt((with.variance + without.variance) / 20000.0);
        EXPECT_NEAR(with.mean, without.mean, 4.0 * standardError) << "roughness " << roughness;
        EXPECT_GT(with.mean, 0.0);
        std::printf("roughness %.2f: mean %.4g vs %.4g, variance %.4g with MIS, %.4g without\n", roughness,
                    with.mean, without.mean, with.variance, without.variance);
        // A small light on a shiny surface: light samples alone are noisy, MIS is not. Where light samples
        // are already good, MIS stays close to them (the power heuristic is near-optimal, Veach 1997).
        if (roughness < 0.1f) {
            EXPECT_LT(with.variance, 0.01 * without.variance) << "roughness " << roughness;
        } else {
            EXPECT_LE(with.variance, 1.25 * without.variance) << "roughness " << roughness;
        }
    }
}

// A Lambertian floor 1e5 and 1e6 from the scene's middle under a sphere lamp 10 above it: there new rays
// leave 0.38 and 3.8 above the floor (VKRT_RAY_OFFSET_EPSILON times the coordinates). Light samples are drawn
// from the hit point; the lamp's hit by the floor's cosine-sampled ray must be weighed by the density seen
// from that point too (seen from the offset origin, the lamp looked larger and MIS made the floor 2.8%
// and 2.2 times too bright).
TEST(ReferenceRenderer, MultipleImportanceSamplingFarFromTheMiddleMatchesClosedForm) {
    for (const float x : {1e5f, 1e6f}) {
        constexpr float height = 10.0f, radius = 6.0f;
        Scene scene;
        scene.materials.push_back(lambert(glm::vec3(0.5f)));
        addFlatQuad(scene, {x - 10, -10, 0}, {x + 10, -10, 0}, {x + 10, 10, 0}, {x - 10, 10, 0}, 0);
        Material lamp = lambert(glm::vec3(0.0f));
        lamp.emission = glm::vec3(1.0f);
        scene.materials.push_back(lamp);
        scene.spheres.push_back({{x, 0.0f, height}, radius, 1});
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        RenderSettings settings = quietSettings();
        settings.integrator = Integrator::Path;
        settings.maxDepth = 1;
        // A sphere of radiance 1 wholly above the plane: irradiance pi sin^2(alpha), radiance albedo
        // sin^2(alpha).
        const double sin2 = double(radius) * radius / (double(height) * height), expected = 0.5 * sin2;
        for (bool mis : {false, true}) {
            settings.multipleImportanceSampling = mis;
            const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
            constexpr int samples = 20000;
            double sum = 0.0, sumSquares = 0.0;
            for (int s = 0; s < samples; ++s) {
                RayCounters counters;
                const double L =
                    renderer
                        .radiance({{x, 0.0, 1.0}, {0.0, 0.0, -1.0}}, 7, static_cast<uint32_t>(s), counters)
                        .x;
                sum += L;
                sumSquares += L * L;
            }
            const double mean = sum / samples;
            const double standardError =
                std::sqrt(std::max(0.0, sumSquares / samples - mean * mean) / samples);
            std::printf("x %g MIS %d: %.5f, closed form %.5f (standard error %.5f)\n", x, int(mis), mean,
                        expected, standardError);
            // What the offset origin still changes (the BSDF ray meets the lamp from nearer): 0.7% and 8%.
            const double allowance = x < 5e5f ? 0.015 : 0.1;
            EXPECT_NEAR(mean, expected, allowance * expected + 4.0 * standardError)
                << "x " << x << ", MIS " << mis;
        }
    }
}

// A small emitter (about a pixel wide) on the axis at distance `z`, seen through a thin lens of radius 0.05
// focused at 4. Returns the diameter of the uniform disk with the same radial second moment as the spot,
// E[r^2] = D^2 / 8, measured about the image centre: moments average the lens-sampling noise out.
double spotDiameter(double z, int size) {
    Scene scene;
    Material lamp = lambert(glm::vec3(0.0f));
    lamp.emission = glm::vec3(1000.0f);
    lamp.doubleSided = true;
    scene.materials.push_back(lamp);
    const float s = static_cast<float>(7e-4 * z);
    const float depth = static_cast<float>(-z);
    addFlatQuad(scene, {-s, -s, depth}, {s, -s, depth}, {s, s, depth}, {-s, s, depth}, 0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera;  // at the origin, looking down -z
    camera.yfov = 0.3;
    camera.aperture = 0.05;
    camera.focusDistance = 4.0;
    RenderSettings settings = quietSettings();
    settings.width = settings.height = size;
    settings.samplesPerPixel = 256;
    const Image image = ReferenceRenderer(scene, bvh, camera, settings).render().image;
    double total = 0.0, moment = 0.0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const double dx = x + 0.5 - 0.5 * size, dy = y + 0.5 - 0.5 * size;
            total += image.at(x, y).x;
            moment += image.at(x, y).x * (dx * dx + dy * dy);
        }
    }
    return std::sqrt(8.0 * moment / total);
}

TEST(ReferenceRenderer, ThinLensBlursToTheCircleOfConfusion) {
    const int size = 96;
    // On the focal plane the point stays sharp (the spot is about a pixel).
    EXPECT_LE(spotDiameter(4.0, size), 2.0);
    // Off it, the blur circle on the focal plane has diameter 2 A |z - f| / z; in pixels that is divided by
    // the height of the view at the focal plane, 2 f tan(yfov / 2), and multiplied by the image height.
    for (double z : {2.0, 3.0, 8.0}) {
        const double circle = 2.0 * 0.05 * std::abs(z - 4.0) / z;
        const double expected = circle / (2.0 * 4.0 * std::tan(0.15)) * size;
        const double measured = spotDiameter(z, size);
        std::printf("z %.1f: spot %.2f px, thin-lens formula %.2f px\n", z, measured, expected);
        EXPECT_NEAR(measured, expected, 0.1 * expected + 1.0) << "z = " << z;
    }
}

TEST(ReferenceRenderer, MoreLightSamplesLowerTheVarianceNotTheMean) {
    // The floor under a square emitter: the radiance at one point, estimated many times.
    Scene scene = floorScene(0.8f);
    Material emitter = lambert(glm::vec3(0.0f));
    emitter.emission = glm::vec3(5.0f);
    scene.materials.push_back(emitter);
    addFlatQuad(scene, {-0.5f, -0.5f, 1.2f}, {-0.5f, 0.5f, 1.2f}, {0.5f, 0.5f, 1.2f}, {0.5f, -0.5f, 1.2f}, 1);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    auto statistics = [&](int lightSamples) {
        RenderSettings settings = quietSettings();
        settings.lightSamples = lightSamples;
        const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
        double sum = 0.0, sumSquares = 0.0;
        const int n = 4000;
        for (int s = 0; s < n; ++s) {
            RayCounters counters;
            const double L =
                renderer.radiance({{0.3, 0.1, 0.5}, {0.0, 0.0, -1.0}}, 3, static_cast<uint32_t>(s), counters)
                    .x;
            sum += L;
            sumSquares += L * L;
        }
        const double mean = sum / n;
        return std::make_pair(mean, sumSquares / n - mean * mean);
    };
    const auto [meanOne, varianceOne] = statistics(1);
    const auto [meanEight, varianceEight] = statistics(8);
    EXPECT_NEAR(meanEight, meanOne, 4.0 * std::sqrt(varianceOne / 4000));
    // Eight independent samples: an eighth of the variance (a quarter allows for sampling error).
    EXPECT_LT(varianceEight, 0.25 * varianceOne);
    EXPECT_GT(varianceEight, 0.06 * varianceOne);
}

TEST(ReferenceRenderer, ACoincidentSurfaceBehindTheOneInFrontIsNotThere) {
    // Two emitters on the same square, red in front (the smaller index wins the tie, README "Deterministic
    // ties") and green behind it, over a floor: the floor sees the red one alone, whatever the light samples.
    // Before, only the one of the same material was removed as a duplicate: the green one stayed among the
    // lights, so light samples brought its light while rays that met the square saw red, and the floor's
    // green changed with --light-samples (0.936 of red with one, 0.997 with four). A square of the reverse
    // winding (its back to the floor, another surface) stays.
    Scene scene = floorScene(0.8f);
    for (const glm::vec3 emission : {glm::vec3(5.0f, 0.0f, 0.0f), glm::vec3(0.0f, 5.0f, 0.0f)}) {
        Material emitter = lambert(glm::vec3(0.0f));
        emitter.emission = emission;
        scene.materials.push_back(emitter);
        addFlatQuad(scene, {-0.5f, -0.5f, 1.2f}, {-0.5f, 0.5f, 1.2f}, {0.5f, 0.5f, 1.2f}, {0.5f, -0.5f, 1.2f},
                    static_cast<uint32_t>(scene.materials.size() - 1));
    }
    addFlatQuad(scene, {-0.5f, -0.5f, 1.2f}, {0.5f, -0.5f, 1.2f}, {0.5f, 0.5f, 1.2f}, {-0.5f, 0.5f, 1.2f}, 2);
    const size_t before = scene.triangles.size();
    finalizeScene(scene);
    EXPECT_EQ(scene.triangles.size(), before - 2);
    EXPECT_EQ(scene.emissiveTriangles.size(), 4u);
    const FlatBvh bvh = bvhFor(scene);
    for (const int lightSamples : {1, 4}) {
        RenderSettings settings = quietSettings();
        settings.lightSamples = lightSamples;
        const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
        glm::dvec3 sum(0.0);
        for (uint32_t s = 0; s < 2000; ++s) {
            RayCounters counters;
            sum += renderer.radiance({{0.3, 0.1, 0.5}, {0.0, 0.0, -1.0}}, 3, s, counters);
        }
        EXPECT_GT(sum.x, 0.0) << lightSamples << " light samples";
        EXPECT_EQ(sum.y, 0.0) << lightSamples << " light samples";
    }
}

TEST(ReferenceRenderer, PixelFiltersBlurAnEdgeByTheirCdf) {
    // An orthographic view of a plane that emits 1 left of x = 0.3 and nothing right of it: each pixel's
    // value is the filter's CDF at the distance from its centre to the edge (box: the covered fraction).
    Scene scene;
    Material glow = lambert(glm::vec3(0.0f));
    glow.emission = glm::vec3(1.0f);
    scene.materials = {glow, lambert(glm::vec3(0.0f))};
    const float edge = 0.3f;
    addFlatQuad(scene, {-100, -100, 0}, {edge, -100, 0}, {edge, 100, 0}, {-100, 100, 0}, 0);
    addFlatQuad(scene, {edge, -100, 0}, {100, -100, 0}, {100, 100, 0}, {edge, 100, 0}, 1);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.0, 0.0, 10.0};
    camera.forward = {0.0, 0.0, -1.0};
    camera.right = {1.0, 0.0, 0.0};
    camera.xmag = camera.ymag = 8.0;  // 16 pixels over 16 units: film x = world x + 8
    RenderSettings settings = quietSettings();
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 4096;
    auto tentCdf = [](double d) {
        if (d <= -1.0) return 0.0;
        if (d <= 0.0) return 0.5 * (d + 1.0) * (d + 1.0);
        if (d <= 1.0) return 1.0 - 0.5 * (1.0 - d) * (1.0 - d);
        return 1.0;
    };
    for (PixelFilter filter : {PixelFilter::Box, PixelFilter::Tent, PixelFilter::Gaussian}) {
        settings.pixelFilter = filter;
        const Image image = ReferenceRenderer(scene, bvh, camera, settings).render().image;
        for (int x = 5; x <= 11; ++x) {
            const double d = (edge + 8.0) - (x + 0.5);  // edge minus pixel centre, in pixels
            const double expected = filter == PixelFilter::Box ? std::clamp(d + 0.5, 0.0, 1.0)
                                    : filter == PixelFilter::Tent
                                        ? tentCdf(d)
                                        : 0.5 * (1.0 + std::erf(d / (0.5 * std::sqrt(2.0))));
            EXPECT_NEAR(image.at(x, 8).x, expected, 0.02)
                << "filter " << static_cast<int>(filter) << ", x " << x;
        }
    }
}

// Glass of ior 1 (no refraction, no Fresnel) with attenuation colour c = (0.5, 0.75, 1) at distance 0.25.
Material attenuatingGlass() {
    Material glass = lambert(glm::vec3(1.0f));
    glass.transmission = 1.0f;
    glass.thickness = 0.5f;
    glass.attenuationColor = {0.5f, 0.75f, 1.0f};
    glass.attenuationDistance = 0.25f;
    return glass;
}

// Looking down through a slab of attenuatingGlass() 0.5 thick onto a white background: transmittance
// c^(0.5 / 0.25) = c^2 per channel.
void expectSlabTransmittance(Scene& scene) {
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings = quietSettings();
    settings.background = glm::dvec3(1.0);
    const ReferenceRenderer renderer(scene, bvh, frameBounds(scene.bounds, 1.0), settings);
    const glm::dvec3 L = radianceDown(renderer, 0.1, 0.2);
    // The ray inside starts VKRT_RAY_OFFSET_EPSILON of its hit point's error scale (|origin| + t, at most 8
    // here) off the entry face, as on the GPU, so the path inside is up to that much shorter than 0.5 and
    // never longer: each channel lies between c^(0.5 / 0.25) and c^((0.5 - offset) / 0.25), a window of about
    // 1e-4 relative.
    const double offset = VKRT_RAY_OFFSET_EPSILON * 8.0;
    for (const auto& [channel, c] : {std::pair{0, 0.5}, std::pair{1, 0.75}}) {
        EXPECT_GE(L[channel], std::pow(c, 0.5 / 0.25) * (1.0 - 1e-12)) << channel;
        EXPECT_LE(L[channel], std::pow(c, (0.5 - offset) / 0.25)) << channel;
    }
    EXPECT_NEAR(L.z, 1.0, 1e-7);
}

TEST(ReferenceRenderer, BeersLawThroughAnIndexMatchedSlab) {
    Scene scene;
    scene.materials.push_back(attenuatingGlass());
    const glm::vec3 corners[4] = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
    addFlatQuad(scene, corners[0], corners[1], corners[2], corners[3], 0);  // top, facing +z
    addFlatQuad(scene, corners[3] - glm::vec3(0, 0, 0.5f), corners[2] - glm::vec3(0, 0, 0.5f),
                corners[1] - glm::vec3(0, 0, 0.5f), corners[0] - glm::vec3(0, 0, 0.5f),
                0);  // bottom, facing -z
    expectSlabTransmittance(scene);
}

// The same through a CSG solid: the slab is the intersection of two boxes that overlap over z in [-0.5, 0]
// (the top face is one box's, the bottom the other's), so the path inside is measured across the two
// operands.
TEST(ReferenceRenderer, BeersLawThroughAnIndexMatchedCsgSlab) {
    Scene scene;
    scene.materials.push_back(attenuatingGlass());
    auto box = [](double zMin, double zMax) {
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), {0.0, 0.0, 0.5 * (zMin + zMax)});
        return makeShape(VKRT_SHAPE_BOX, 0, glm::scale(m, {5.0, 5.0, 0.5 * (zMax - zMin)}));
    };
    // Inside both boxes: state 3 (bits 0 and 1).
    addSolid(scene, {box(-0.5, 0.25), box(-0.75, 0.0)}, {1u << 3});
    expectSlabTransmittance(scene);
}

// The Cornell box, loaded once per test, rendered small.
class CornellBox : public ::testing::Test {
  protected:
    RenderResult render(int size, int samplesPerPixel, uint32_t seed = 0, int threads = 0) const {
        RenderRequest request;
        request.settings.width = size;
        request.height = size;
        request.settings.samplesPerPixel = samplesPerPixel;
        request.settings.seed = seed;
        request.settings.threads = threads;
        const RenderSetup setup = resolveRender(request, scene);
        return ReferenceRenderer(scene, bvh, setup.camera, setup.settings).render();
    }

    const Scene scene = loadGltf((test::sourceDir() / "scenes/cornell.gltf").string());
    const FlatBvh bvh = bvhFor(scene);
};

TEST_F(CornellBox, IsRecognisable) {
    const RenderResult result = render(48, 4);
    EXPECT_EQ(result.rays.nonFiniteSamples, 0u);
    EXPECT_EQ(result.rays.primary, 48u * 48u * 4u);
    auto meanOver = [&](int x0, int x1, int y0, int y1) {
        glm::dvec3 sum(0.0);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) sum += glm::dvec3(result.image.at(x, y));
        return sum / static_cast<double>((x1 - x0) * (y1 - y0));
    };
    const glm::dvec3 left = meanOver(2, 6, 12, 36), right = meanOver(42, 46, 12, 36);
    EXPECT_GT(left.x, 2.0 * left.y) << "the left wall is red";
    EXPECT_GT(right.y, 2.0 * right.x) << "the right wall is green";
    // The light in the ceiling is the brightest thing in view.
    const glm::dvec3 lamp = meanOver(22, 26, 6, 8);  // rows 5.95 to 7.63 and columns 20 to 28 see it
    EXPECT_GT(lamp.x, 5.0);
    const glm::dvec3 floor = meanOver(20, 28, 44, 47);
    EXPECT_GT(floor.x, 0.05);
}

TEST_F(CornellBox, SamplesBeyondFloatsRangeAreLeftOutAndCounted) {
    // The lamp at 2e37 times its emission (red 17): its own pixels are 3.4e37, but the light near it reflects
    // beyond float's range in some samples, which the double-precision sums kept and the image wrote as
    // infinity.
    Scene bright = scene;
    for (Material& material : bright.materials) material.emission *= 2e37f;
    RenderRequest request;
    request.settings.width = 32;
    request.height = 32;
    request.settings.samplesPerPixel = 8;
    const RenderSetup setup = resolveRender(request, bright);
    const RenderResult result =
        ReferenceRenderer(bright, bvhFor(bright), setup.camera, setup.settings).render();
    EXPECT_GT(result.rays.nonFiniteSamples, 0u);
    EXPECT_EQ(result.samplesKept, 32u * 32u * 8u - result.rays.nonFiniteSamples);
    for (const glm::vec3& p : result.image.pixels) {
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    }
}

TEST_F(CornellBox, SameSeedSameImageOtherSeedOtherNoise) {
    const Image a = render(24, 2).image;
    const Image b = render(24, 2, 0, 1).image;
    const Image c = render(24, 2, 1).image;
    EXPECT_EQ(compareImages(a, b).rmse, 0.0) << "threads must not change the result";
    EXPECT_GT(compareImages(a, c).rmse, 0.0);
}

TEST(ReferenceRenderer, WhittedSceneHasNoNonFiniteSamplesAndTracesSecondaryRays) {
    const Scene scene = loadGltf((test::sourceDir() / "scenes/whitted.gltf").string());
    const FlatBvh bvh = bvhFor(scene);
    RenderRequest request;
    request.settings.width = 40;
    request.height = 30;
    request.settings.samplesPerPixel = 1;
    RenderSetup setup = resolveRender(request, scene);
    const RenderResult result = ReferenceRenderer(scene, bvh, setup.camera, setup.settings).render();
    EXPECT_EQ(result.rays.nonFiniteSamples, 0u);
    EXPECT_GT(result.rays.secondary, 100u);
    // Depth 0 traces no reflection or refraction at all.
    setup.settings.maxDepth = 0;
    const RenderResult flat = ReferenceRenderer(scene, bvh, setup.camera, setup.settings).render();
    EXPECT_EQ(flat.rays.secondary, 0u);
}

}  // namespace
}  // namespace vkrt
