// What a surface's normal texture, alpha, unlit and transmission texture do, with known answers, on the GPU
// and the CPU reference alike: a normal map turns the shading normal by the angle its texel encodes, in the
// tangent frame and with its scale; alpha MASK cuts holes that camera rays and shadow rays pass, and alpha
// BLEND covers the fraction alpha of a point, for camera rays and for shadow rays; an unlit material shows its
// base colour; the transmission texture's red multiplies the transmission factor; a clear coat dims the base by
// its Fresnel reflectance and reflects that much; sheen reflects its albedo and takes it from the base; ray
// cones pick mipmap levels.
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gpu/scene_features.h"
#include "scene/scene_builder.h"
#include "scene/sheen_table.h"
#include "scene/tangent_frames.h"
#include "shape_geometry.h"
#include "sheen.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using test::ambientOnly;
using test::lambertian;
using test::Gpu;
using test::textureOf;

// One RGBA8 texel encoding the unit tangent-space normal n (each component c stored as (c + 1) / 2), and
// the normal the renderers decode from it.
uint32_t normalTexel(const glm::dvec3& n) {
    uint32_t texel = 0xff000000u;
    for (int c = 0; c < 3; ++c) texel |= static_cast<uint32_t>(std::lround((n[c] + 1.0) * 0.5 * 255.0)) << (8 * c);
    return texel;
}
glm::dvec3 decodedNormal(uint32_t texel) {
    glm::dvec3 n;
    for (int c = 0; c < 3; ++c) n[c] = ((texel >> (8 * c)) & 0xffu) / 255.0 * 2.0 - 1.0;
    return n;
}

// A directional light of illuminance `illuminance` arriving from direction `toLight`.
PunctualLight sunFrom(const glm::dvec3& toLight, float illuminance) {
    PunctualLight sun;
    sun.type = LightType::Directional;
    sun.direction = -toLight;
    sun.intensity = illuminance;
    return sun;
}

// A medium of index 1 that absorbs half the light per unit, bounded by a white surface of alpha `alpha` under
// `mode`.
Material absorbingMedium(float alpha, AlphaMode mode) {
    Material medium = test::lambertian(1.0f);
    medium.transmission = 1.0f;
    medium.thickness = 1.0f;
    medium.ior = 1.0f;
    medium.attenuationColor = glm::vec3(0.5f);
    medium.attenuationDistance = 1.0f;
    medium.baseColor.a = alpha;
    medium.alphaMode = mode;
    return medium;
}

// A surface that is a hole everywhere (MASK, alpha 0).
Material allHole() {
    Material hole = test::lambertian(1.0f);
    hole.baseColor.a = 0.0f;
    hole.alphaMode = AlphaMode::Mask;
    return hole;
}

// The corners, counter-clockwise seen from above, of the square [lo, hi]^2 lifted onto the slanted plane
// z = height + slope.x x + slope.y y, whose distances along rays round differently on different triangles.
std::array<glm::vec3, 4> slantedSquare(float lo, float hi, float height, glm::vec2 slope) {
    const auto lifted = [&](float x, float y) { return glm::vec3(x, y, height + slope.x * x + slope.y * y); };
    return {lifted(lo, lo), lifted(hi, lo), lifted(hi, hi), lifted(lo, hi)};
}

RenderSettings litOnly(int size) {
    RenderSettings settings = ambientOnly(size);
    settings.ambient = glm::dvec3(0.0);
    settings.background = glm::dvec3(0.0);
    return settings;
}

// `scene` seen by the sphere camera (test::sphereCamera) against a background of 1 and lit by nothing else,
// at 16 samples, with each integrator (paths, then Whitted's), on both devices.
std::vector<std::pair<const char*, test::RenderPair>> againstWhite(const VulkanContext& context,
                                                                   const Scene& scene) {
    std::vector<std::pair<const char*, test::RenderPair>> renders;
    for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        RenderSettings settings = litOnly(16);
        settings.integrator = integrator;
        settings.background = glm::dvec3(1.0);
        settings.samplesPerPixel = 16;
        renders.emplace_back(integrator == Integrator::Path ? "paths" : "Whitted",
                             test::renderGpuAndCpu(context, scene, test::bvhFor(scene), test::sphereCamera(),
                                                   settings, test::shaderCacheDir()));
    }
    return renders;
}

using test::meanRed;

class GpuSurfaces : public Gpu {};

TEST_F(GpuSurfaces, NormalMapTurnsTheShadingNormal) {
    // The unit square (texture coordinates (x, 1 - y)) has the tangent frame T = +x, bitangent w cross(n, T) =
    // w (+y). Its normal texture's one texel tilts the normal by 40 degrees towards the bitangent. Under a sun
    // from toLight, a Lambertian surface shows albedo / pi * E * dot(n', toLight), where n' is the decoded
    // normal in the frame, its x and y scaled by the normal scale and normalised; w = -1 mirrors the tilt,
    // scale 0 removes it.
    const double tilt = 40.0 * M_PI / 180.0;
    const uint32_t texel = normalTexel({0.0, std::sin(tilt), std::cos(tilt)});
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.2, 0.8, 1.0));
    const double albedo = 0.7, illuminance = 3.0;
    struct Case {
        float w, scale;
    };
    for (const Case c : {Case{1.0f, 1.0f}, Case{-1.0f, 1.0f}, Case{1.0f, 0.5f}, Case{1.0f, 0.0f}}) {
        SCOPED_TRACE(testing::Message() << "w " << c.w << ", scale " << c.scale);
        Scene scene;
        scene.textures.push_back(textureOf(1, 1, {texel}));
        scene.lights.push_back(sunFrom(toLight, static_cast<float>(illuminance)));
        Material material = lambertian(static_cast<float>(albedo));
        material.normalTexture.texture = 0;
        material.normalScale = c.scale;
        const glm::vec4 tangent(1.0f, 0.0f, 0.0f, c.w);
        scene.tangents.assign(2, {tangent, tangent, tangent});
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, litOnly(16));
        const glm::dvec3 t = decodedNormal(texel) * glm::dvec3(c.scale, c.scale, 1.0);
        const glm::dvec3 mapped = glm::normalize(glm::dvec3(t.x, c.w * t.y, t.z));
        const double expected = albedo / M_PI * illuminance * glm::dot(mapped, toLight);
        for (const Image* image : {&gpu.image, &cpu.image}) EXPECT_NEAR(image->at(8, 8).x, expected, 2e-6);
    }
}

TEST_F(GpuSurfaces, NormalMapTiltedBy60DegreesHalvesTheRadiance) {
    // Under a head-on sun, a normal texture that tilts the normal by 60 degrees (about the tangent, as
    // encoded in 8 bits) halves the Lambertian radiance, with the tangent frames given and with the frames
    // derived from the square's texture coordinates (tangent_frames.h), which must be the same frame.
    const double tilt = 60.0 * M_PI / 180.0;
    const uint32_t texel = normalTexel({std::sin(tilt), 0.0, std::cos(tilt)});
    const double albedo = 0.8, illuminance = 2.0, flat = albedo / M_PI * illuminance;
    // The square's corners (0,0), (1,0), (1,1), (0,1) with texture coordinates (x, 1 - y) and normal +z.
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> uvs = {0, 1, 1, 1, 1, 0, 0, 0};
    const std::vector<float> derived = vertexTangents(positions, normals, uvs, {{0, 1, 2}, {0, 2, 3}}).frames;
    const glm::vec4 given(1.0f, 0.0f, 0.0f, 1.0f);
    for (const bool derive : {false, true}) {
        SCOPED_TRACE(derive ? "derived tangents" : "given tangents");
        Scene scene;
        scene.textures.push_back(textureOf(1, 1, {texel}));
        scene.lights.push_back(sunFrom({0.0, 0.0, 1.0}, static_cast<float>(illuminance)));
        Material material = lambertian(static_cast<float>(albedo));
        material.normalTexture.texture = 0;
        auto frame = [&](int v) { return derive ? glm::make_vec4(&derived[4 * v]) : given; };
        scene.tangents = {{frame(0), frame(1), frame(2)}, {frame(0), frame(2), frame(3)}};
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, litOnly(8));
        const double cosine = glm::normalize(decodedNormal(texel)).z;  // 0.5, to the texel's 8 bits
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_NEAR(image->at(4, 4).x, flat * cosine, 2e-6);
            EXPECT_NEAR(image->at(4, 4).x / flat, 0.5, 0.01);
        }
    }
}

TEST_F(GpuSurfaces, NormalTexturesOnShapesAndSpheresFollowTheirTextureTransform) {
    // The top face of a box (a VKRT_shape), filling the square camera's view: its u runs along +x and v down
    // +y's opposite, so the tangent is +x and the bitangent +y. Its normal texture's one texel tilts the
    // normal by 40 degrees towards the tangent. A KHR_texture_transform that turns the texture a quarter turn
    // makes the transformed u' run along -y and v' along -x: the tilt points to -y (the bitangent to +x); one
    // that mirrors u makes it point to -x (the bitangent stays). Under a sun from toLight the face shows
    // albedo / pi * E * dot(n', toLight). On a VKRT_sphere the mirrored texture tilts the other way, as a
    // texel tilted the other way does. Spheres' and shapes' frames ignored the transform (a warning said so):
    // the tilt pointed to +x in every case.
    const double tilt = 40.0 * M_PI / 180.0;
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(-0.5, -0.6, 1.0));
    const double albedo = 0.7, illuminance = 3.0;
    struct Case {
        const char* name;
        float rotation;
        glm::vec2 scale;
        glm::dvec3 tangent, bitangent;  // the transformed frame's
    };
    for (const Case& c :
         {Case{"a quarter turn", float(M_PI / 2.0), {1.0f, 1.0f}, {0.0, -1.0, 0.0}, {1.0, 0.0, 0.0}},
          Case{"mirrored", 0.0f, {-1.0f, 1.0f}, {-1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}}}) {
        SCOPED_TRACE(c.name);
        const uint32_t texel = normalTexel({std::sin(tilt), 0.0, std::cos(tilt)});
        Scene scene;
        scene.textures.push_back(textureOf(1, 1, {texel}));
        scene.lights.push_back(sunFrom(toLight, static_cast<float>(illuminance)));
        Material material = lambertian(static_cast<float>(albedo));
        material.normalTexture.texture = 0;
        material.normalTexture.rotation = c.rotation;
        material.normalTexture.scale = c.scale;
        scene.materials.push_back(material);
        const glm::dmat4 box = glm::scale(glm::translate(glm::dmat4(1.0), {0.5, 0.5, -0.5}), glm::dvec3(0.5));
        addSolid(scene, {makeShape(VKRT_SHAPE_BOX, 0, box)}, {2u, 0u, 0u, 0u, 0u, 0u, 0u, 0u});
        finalizeScene(scene);
        const auto [gpu, cpu] = test::renderGpuAndCpu(
            context(), scene, test::bvhFor(scene), test::squareCamera(), litOnly(16), test::shaderCacheDir());
        const glm::dvec3 t = decodedNormal(texel);
        const glm::dvec3 mapped =
            glm::normalize(t.x * c.tangent + t.y * c.bitangent + glm::dvec3(0.0, 0.0, t.z));
        const double expected = albedo / M_PI * illuminance * glm::dot(mapped, toLight);
        for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}})
            EXPECT_NEAR(image->at(8, 8).x, expected, 2e-6) << device;
    }
    // The sphere: mirrored, against the texel tilted the other way, unmirrored.
    std::array<test::RenderPair, 2> spheres;
    for (const bool mirrored : {false, true}) {
        Scene scene;
        scene.textures.push_back(
            textureOf(1, 1, {normalTexel({(mirrored ? 1.0 : -1.0) * std::sin(tilt), 0.0, std::cos(tilt)})}));
        scene.lights.push_back(sunFrom(toLight, static_cast<float>(illuminance)));
        Material material = lambertian(static_cast<float>(albedo));
        material.normalTexture.texture = 0;
        if (mirrored) material.normalTexture.scale = {-1.0f, 1.0f};
        scene.materials.push_back(material);
        scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
        finalizeScene(scene);
        spheres[mirrored] = test::renderGpuAndCpu(context(), scene, test::bvhFor(scene), test::sphereCamera(),
                                                  litOnly(16), test::shaderCacheDir());
    }
    ASSERT_GT(meanRed(spheres[0].cpu.image), 0.05);
    for (const auto& [device, plain, mirrored] :
         {std::tuple{"GPU", &spheres[0].gpu.image, &spheres[1].gpu.image},
          std::tuple{"CPU", &spheres[0].cpu.image, &spheres[1].cpu.image}}) {
        int apart = 0;
        for (int y = 0; y < plain->height; ++y)
            for (int x = 0; x < plain->width; ++x)
                apart += std::abs(plain->at(x, y).x - mirrored->at(x, y).x) > 1e-5f;
        EXPECT_EQ(apart, 0) << device;
    }
}

TEST_F(GpuSurfaces, AlphaMaskCutsHoles) {
    // A texture whose left texel has alpha 200/255 and right texel 100/255: with cutoff 0.5 the left half is
    // the surface (albedo 1 under ambient 1) and the right half a hole showing the background (0.25); raising
    // the cutoff above 200/255 leaves nothing; OPAQUE ignores alpha.
    struct Case {
        AlphaMode mode;
        float cutoff;
        double left, right;
    };
    for (const Case c : {Case{AlphaMode::Mask, 0.5f, 1.0, 0.25}, Case{AlphaMode::Mask, 0.8f, 0.25, 0.25},
                         Case{AlphaMode::Opaque, 0.5f, 1.0, 1.0}}) {
        SCOPED_TRACE(testing::Message() << "cutoff " << c.cutoff);
        Scene scene;
        scene.textures.push_back(textureOf(2, 1, {0xc8ffffffu, 0x64ffffffu}));
        Material material = lambertian(1.0f);
        material.baseColorTexture.texture = 0;
        material.alphaMode = c.mode;
        material.alphaCutoff = c.cutoff;
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(16));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_NEAR(image->at(3, 8).x, c.left, 1e-6);
            EXPECT_NEAR(image->at(12, 8).x, c.right, 1e-6);
        }
    }
}

TEST_F(GpuSurfaces, AlphaEqualToTheCutoffIsOpaqueWithVertexColours) {
    // Alpha exactly at the cutoff is the surface (glTF: alpha >= alphaCutoff). With vertex colours in the
    // scene every triangle's COLOR_0 (white where it has none) multiplies alpha, and white corners
    // interpolated with weights that summed to 1 in rounded arithmetic gave 0.99999994: holes in some pixels,
    // different on the two devices.
    Scene scene;
    scene.materials.push_back(lambertian(0.0f));
    addFlatQuad(scene, {5.0f, 5.0f, 0.0f}, {6.0f, 5.0f, 0.0f}, {6.0f, 6.0f, 0.0f}, {5.0f, 6.0f, 0.0f}, 0);
    scene.vertexColors.assign(scene.triangles.size(), {glm::vec4(1.0f), glm::vec4(1.0f), glm::vec4(1.0f)});
    Material material = lambertian(1.0f);
    material.baseColor.a = 0.5f;
    material.alphaMode = AlphaMode::Mask;
    material.alphaCutoff = 0.5f;
    RenderSettings settings = ambientOnly(32);
    settings.samplesPerPixel = 16;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, settings);
    for (const Image* image : {&gpu.image, &cpu.image}) {
        int holes = 0;
        for (int y = 0; y < image->height; ++y)
            for (int x = 0; x < image->width; ++x) holes += std::abs(image->at(x, y).x - 1.0f) > 1e-6f;
        EXPECT_EQ(holes, 0);
    }
}

TEST_F(GpuSurfaces, LightsPastTheLoopBudgetAreNeverSilentlyDropped) {
    // 20,000 point lights over the unit square: llvmpipe ends an invocation's loops after 65535 passes, and
    // its light loop once stopped after 16,384 lights, keeping the sample (the floor 0.82 of the CPU's) with
    // nothing said. Each sample is either whole, as the CPU's, or left out and counted.
    Scene scene;
    constexpr int kLights = 20000;
    for (int i = 0; i < kLights; ++i) {
        PunctualLight light;
        light.position = {0.5 + 0.3 * std::cos(i), 0.5 + 0.3 * std::sin(i), 1.0};
        light.intensity = 10.0f / kLights;
        scene.lights.push_back(light);
    }
    RenderSettings settings = litOnly(4);
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(0.5f), settings);
    ASSERT_GT(meanRed(cpu.image), 0.1);
    if (gpu.rays.nonFiniteSamples == 0) {
        EXPECT_NEAR(meanRed(gpu.image) / meanRed(cpu.image), 1.0, 1e-3);
    } else {
        EXPECT_EQ(gpu.rays.nonFiniteSamples, 16u * settings.samplesPerPixel)
            << "every sample ran out, or none";
    }
}

TEST_F(GpuSurfaces, AlphaBlendCoversTheFractionAlpha) {
    // A surface of alpha 0.3 in front of the background: each camera ray goes through with probability 0.7, so
    // the image converges to 0.3 * 1 + 0.7 * 0.25. Both devices draw the same numbers: the images agree.
    Scene scene;
    Material material = lambertian(1.0f);
    material.baseColor.a = 0.3f;
    material.alphaMode = AlphaMode::Blend;
    RenderSettings settings = ambientOnly(32);
    settings.samplesPerPixel = 64;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, settings);
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(meanRed(*image), 0.3 + 0.7 * 0.25, 0.005);
        // Every pixel is a mix: the decisions are stratified over each pixel's samples.
        EXPECT_NEAR(image->at(5, 9).x, 0.475, 0.03);
    }
    test::expectMatchesReference(gpu.image, cpu.image, "alpha-blend");
}

TEST_F(GpuSurfaces, HolesInAVolumesSurfaceLeaveItsMediumWhole) {
    // A sphere of radius 1 bounding an absorbing medium of index 1 (attenuation 0.5 per unit), its surface
    // covering half of each point (BLEND, alpha 0.5), against a background of 1, seen by an orthographic
    // camera. Alpha takes the interface away at its holes, not the medium: every ray crosses the medium along
    // its chord 2 sqrt(1 - r^2) and brings 0.5^chord back, through the surface or through its holes. A ray
    // that entered through the surface and left through a hole was taken to be inside still, and came back
    // black, and one that entered through a hole was never inside: the centre showed 0.58 where 0.25 is due.
    Scene scene;
    scene.materials.push_back(absorbingMedium(0.5f, AlphaMode::Blend));
    scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
    finalizeScene(scene);
    for (const auto& [integrator, render] : againstWhite(context(), scene)) {
        SCOPED_TRACE(integrator);
        for (const int x : {8, 12}) {
            // Pixel (x, 8)'s mean of 0.5^chord over its area (the film spans [-1, 1]), by the midpoint rule.
            double expected = 0.0;
            for (int i = 0; i < 64; ++i) {
                for (int j = 0; j < 64; ++j) {
                    const double u = (x + (i + 0.5) / 64.0) / 8.0 - 1.0,
                                 v = (8 + (j + 0.5) / 64.0) / 8.0 - 1.0;
                    expected += std::pow(0.5, 2.0 * std::sqrt(1.0 - u * u - v * v)) / (64.0 * 64.0);
                }
            }
            // The samples' stratified positions sum the pixel's area to within the 16 samples' resolution.
            for (const Image* image : {&render.gpu.image, &render.cpu.image})
                EXPECT_NEAR(image->at(x, 8).x, expected, 2e-3) << x;
        }
    }
}

TEST_F(GpuSurfaces, HolesInAMetallicVolumesSurfaceLetRaysIntoItsMedium) {
    // A sphere of radius 1 around an absorbing medium (0.5 per unit), its surface a metal (metallic 1, which
    // transmits nothing, whatever its transmission factor) that is all holes (MASK, alpha 0), against a
    // background of 1: every ray passes in and out through the holes and brings 0.5^chord back, as through a
    // holed dielectric. The scene's shader left volumes out, the surface transmitting nothing, and rays
    // passed the medium on the GPU (1 at the centre), where the CPU absorbed them (0.25).
    Scene scene;
    Material metal = absorbingMedium(0.0f, AlphaMode::Mask);
    metal.metallic = 1.0f;
    scene.materials.push_back(metal);
    scene.spheres.push_back({glm::vec3(0.0f), 1.0f, 0});
    finalizeScene(scene);
    ASSERT_TRUE(detectFeatures(scene).volumes);
    for (const auto& [integrator, render] : againstWhite(context(), scene)) {
        SCOPED_TRACE(integrator);
        // Pixel (8, 8) spans [0, 1/8]^2 of the film: its chords lie within 1e-2 of 2.
        EXPECT_NEAR(render.gpu.image.at(8, 8).x, 0.25, 2e-3) << "GPU";
        EXPECT_NEAR(render.cpu.image.at(8, 8).x, 0.25, 2e-3) << "CPU";
    }
}

TEST_F(GpuSurfaces, RaysThroughHolesLeaveAVolumeThinnerThanATie) {
    // A box solid 4 x 4 wide and 2 h thick around an absorbing medium (0.5 per unit), its surface all holes
    // (MASK, alpha 0), against a background of 1: rays pass in and out and bring 0.5^(2 h) back. At h = 3e-6
    // the sheet is thinner than a tie (2^-20 of the ray's magnitudes): its exit lay in the tie group of its
    // entry, and a walk that went on past the group met it no more: rays stayed inside and came back black
    // (found by a review).
    for (const double half : {0.1, 3e-6}) {
        SCOPED_TRACE(testing::Message() << "half thickness " << half);
        Scene scene;
        scene.materials.push_back(absorbingMedium(0.0f, AlphaMode::Mask));
        addSolid(scene,
                 {makeShape(VKRT_SHAPE_BOX, 0, glm::scale(glm::dmat4(1.0), glm::dvec3(2.0, 2.0, half)))},
                 {2u, 0u, 0u, 0u, 0u, 0u, 0u, 0u});  // inside the one shape
        finalizeScene(scene);
        for (const auto& [integrator, render] : againstWhite(context(), scene)) {
            SCOPED_TRACE(integrator);
            EXPECT_NEAR(render.gpu.image.at(8, 8).x, std::pow(0.5, 2.0 * half), 1e-5) << "GPU";
            EXPECT_NEAR(render.cpu.image.at(8, 8).x, std::pow(0.5, 2.0 * half), 1e-5) << "CPU";
        }
    }
}

TEST_F(GpuSurfaces, PathsShadowRaysEnterAndLeaveVolumesThroughHoles) {
    // The unit square (albedo 1) under a sun from straight above, seen from above by an orthographic camera,
    // with two spheres of radius 0.2 whose surfaces are all holes (MASK, alpha 0) around an absorbing medium
    // of index 1 (0.5 per unit), A's centre on the square, B's above it, and a box of it 0.2 high, a solid,
    // above it too. The camera ray and the shadow ray cross the same medium, so the square shows 0.5^(2 z)
    // under A (z the height of A's top above the point), 0.5^(4 h) under B (2 h its chord) and 0.5^0.4 under
    // the box. A path's shadow ray through holes stayed in the medium it started in: under A it was absorbed
    // all the way to the sun (black), under B and the box not at all.
    Scene scene;
    scene.materials.push_back(absorbingMedium(0.0f, AlphaMode::Mask));
    const double radius = 0.2;
    const glm::dvec3 a(0.3, 0.5, 0.0), b(0.7, 0.5, 0.5);
    scene.spheres.push_back({glm::vec3(a), float(radius), 0});
    scene.spheres.push_back({glm::vec3(b), float(radius), 0});
    // The box over (0.4..0.6, 0.1..0.3).
    const glm::dmat4 box = glm::scale(glm::translate(glm::dmat4(1.0), {0.5, 0.2, 0.5}), glm::dvec3(0.1));
    addSolid(scene, {makeShape(VKRT_SHAPE_BOX, 0, box)},
             {2u, 0u, 0u, 0u, 0u, 0u, 0u, 0u});                     // inside the one shape
    scene.lights.push_back(sunFrom({0.0, 0.0, 1.0}, float(M_PI)));  // radiance 1 from an unshadowed square
    RenderSettings settings = litOnly(32);
    settings.integrator = Integrator::Path;
    settings.samplesPerPixel = 16;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(1.0f), settings);
    ASSERT_TRUE(detectFeatures(scene).volumeHoles);
    const auto expected = [&](int x, int y) {  // the pixel's mean, by the midpoint rule
        double sum = 0.0;
        for (int i = 0; i < 64; ++i) {
            for (int j = 0; j < 64; ++j) {
                const glm::dvec2 p((x + (i + 0.5) / 64.0) / 32.0, 1.0 - (y + (j + 0.5) / 64.0) / 32.0);
                const auto half = [&](const glm::dvec3& c) {  // half the vertical chord through c at p
                    const glm::dvec2 d = p - glm::dvec2(c);
                    return std::sqrt(std::max(radius * radius - glm::dot(d, d), 0.0));
                };
                sum += std::pow(0.5, 2.0 * half(a) + 4.0 * half(b)) / (64.0 * 64.0);
            }
        }
        return sum;
    };
    for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}}) {
        SCOPED_TRACE(device);
        for (const int x : {0, 9, 22}) EXPECT_NEAR(image->at(x, 16).x, expected(x, 16), 2e-3) << x;
        EXPECT_NEAR(image->at(15, 25).x, std::pow(0.5, 0.4), 2e-3) << "under the box";
    }
    EXPECT_NEAR(expected(9, 16), std::pow(0.5, 0.4), 0.01);   // under A's top
    EXPECT_NEAR(expected(22, 16), std::pow(0.5, 0.8), 0.01);  // under B's centre
}

TEST_F(GpuSurfaces, PathsShadowRaysPassMoreThanSixtyFourHoles) {
    // The unit square (albedo 1) under a sun of illuminance pi from straight above: radiance 1. Between the
    // camera and the sun, 65 planes that are holes throughout (MASK, alpha 0). Where a volume's surface has
    // holes somewhere in the scene (here a small absorbing sphere far aside), a path's shadow ray meets its
    // first 64 surfaces in order and leaves the rest to the walk that takes them in any order; elsewhere that
    // walk takes them all, also in the shader with every feature compiled in. A shadow ray that met more than
    // 64 in order was taken to be blocked: black, in the holed scene and in every scene under the
    // all-features shader.
    for (const bool volumeWithHoles : {false, true}) {
        SCOPED_TRACE(volumeWithHoles ? "a volume with holes" : "no volume with holes");
        Scene scene;
        scene.materials.push_back(allHole());
        for (int i = 0; i < 65; ++i) {
            const float z = 1.1f + 0.01f * float(i);
            addFlatQuad(scene, {-1.0f, -1.0f, z}, {2.0f, -1.0f, z}, {2.0f, 2.0f, z}, {-1.0f, 2.0f, z}, 0);
        }
        if (volumeWithHoles) {
            scene.materials.push_back(absorbingMedium(0.0f, AlphaMode::Mask));
            scene.spheres.push_back({glm::vec3(5.0f, 5.0f, 0.5f), 0.1f, 1});
        }
        scene.lights.push_back(sunFrom({0.0, 0.0, 1.0}, float(M_PI)));
        scene.materials.push_back(lambertian(1.0f));
        test::addUnitSquare(scene, static_cast<uint32_t>(scene.materials.size()) - 1);
        finalizeScene(scene);
        EXPECT_EQ(detectFeatures(scene).volumeHoles, volumeWithHoles);
        const FlatBvh bvh = test::bvhFor(scene);
        RenderSettings settings = litOnly(8);
        settings.integrator = Integrator::Path;
        settings.maxDepth = 0;
        GpuRenderOptions everyFeature;
        everyFeature.shaderCacheDir = test::shaderCacheDir();
        everyFeature.allFeatures = true;
        const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, bvh, test::squareCamera(), settings,
                                                      test::shaderCacheDir());
        const Image all = renderGpu(scene, bvh, test::squareCamera(), settings, everyFeature).image;
        for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"},
                                            std::pair{&all, "GPU, every feature"}}) {
            SCOPED_TRACE(device);
            EXPECT_NEAR(meanRed(*image), 1.0, 1e-4);
        }
    }
}

TEST_F(GpuSurfaces, PathsShadowRaysThroughAHoleMeetTheFaceCoincidentWithIt) {
    // The unit square (albedo 1) under a sun from straight above, and between them, out of the camera's view,
    // a leaf made of two coincident faces on a slanted plane, the first all hole (MASK, alpha 0), the second
    // opaque, turned and divided into triangles the other way; a small absorbing sphere with holes far aside
    // makes paths' shadow rays meet surfaces in order. They pass the hole and are stopped by the second face:
    // the square is black. The walk searched on from the hole's distance and missed the second face wherever
    // rounding put it at or before that distance: the square's mean was 0.83 on the GPU, 0.80 on the CPU.
    const auto [a, b, c, d] = slantedSquare(-1.0f, 2.0f, 1.2f, {0.03f, 0.021f});
    Scene scene;
    scene.materials.push_back(allHole());
    Material leaf = lambertian(0.0f);
    leaf.doubleSided = true;
    scene.materials.push_back(leaf);
    addFlatQuad(scene, a, b, c, d, 0);
    addFlatQuad(scene, b, a, d, c, 1);
    scene.materials.push_back(absorbingMedium(0.0f, AlphaMode::Mask));
    scene.spheres.push_back({glm::vec3(5.0f, 5.0f, 0.5f), 0.1f, 2});
    scene.lights.push_back(sunFrom({0.0, 0.0, 1.0}, float(M_PI)));
    RenderSettings settings = litOnly(16);
    settings.integrator = Integrator::Path;
    settings.maxDepth = 0;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(1.0f), settings);
    for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}}) {
        SCOPED_TRACE(device);
        EXPECT_EQ(meanRed(*image), 0.0);
    }
}

TEST_F(GpuSurfaces, TranslucentDoubleSidedSphereLampLightsThroughItsHoles) {
    // A lamp sphere beside the unit square (out of the camera's view), double-sided, of alpha 0.5 (BLEND):
    // along every line through it the near side covers half, and the inside of the far side half of the rest
    // seen through the near side's holes, so it lights the square as 0.75 of the opaque lamp does, by light
    // samples alone (Whitted, no bounce) and by paths (one bounce, weighed against light samples). Light
    // samples drew from the cone of the near half alone, and the square got 0.5 of the opaque lamp's light
    // from Whitted.
    const auto squareMean = [&](bool translucent, Integrator integrator) {
        Scene scene;
        Material lamp = lambertian(0.0f);
        lamp.emission = glm::vec3(4.0f);
        lamp.doubleSided = true;
        if (translucent) {
            lamp.alphaMode = AlphaMode::Blend;
            lamp.baseColor.a = 0.5f;
        }
        scene.materials.push_back(lamp);
        scene.spheres.push_back({glm::vec3(0.5f, -0.6f, 0.8f), 0.4f, 0});
        RenderSettings settings = litOnly(16);
        settings.integrator = integrator;
        settings.maxDepth = integrator == Integrator::Path ? 1 : 0;
        settings.samplesPerPixel = 64;
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(1.0f), settings);
        return std::pair{meanRed(gpu.image), meanRed(cpu.image)};
    };
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        SCOPED_TRACE(integrator == Integrator::Path ? "paths" : "Whitted");
        const auto [opaqueGpu, opaqueCpu] = squareMean(false, integrator);
        const auto [translucentGpu, translucentCpu] = squareMean(true, integrator);
        EXPECT_GT(opaqueGpu, 0.01);
        EXPECT_NEAR(translucentGpu / opaqueGpu, 0.75, 0.01);
        EXPECT_NEAR(translucentCpu / opaqueCpu, 0.75, 0.01);
    }
}

TEST_F(GpuSurfaces, FullyCoveredBlendSphereLampIsSampledAlikeOnBothDevices) {
    // A double-sided sphere lamp of BLEND alpha 1 beside the unit square, nothing else with holes: the GPU's
    // specialised materials take every surface as opaque and sample the lamp by the cone of its near half, as
    // an opaque lamp. The CPU sampled it by area as a lamp seen through: the same expectation, other pixels
    // (98% of them off at 4 samples). Both now draw the same light samples.
    Scene scene;
    Material lamp = lambertian(0.0f);
    lamp.emission = glm::vec3(4.0f);
    lamp.doubleSided = true;
    lamp.alphaMode = AlphaMode::Blend;
    scene.materials.push_back(lamp);
    scene.spheres.push_back({glm::vec3(0.5f, -0.6f, 0.8f), 0.4f, 0});
    EXPECT_FALSE(detectFeatures(scene).alpha);
    RenderSettings settings = litOnly(16);
    settings.samplesPerPixel = 4;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(1.0f), settings);
    test::expectMatchesReference(gpu.image, cpu.image, "fully-covered-sphere-lamp");
}

TEST_F(GpuSurfaces, BlackBlendQuadBeforeAnEmitterLetsThroughOneMinusAlpha) {
    // A black quad of alpha 0.25 (BLEND) in front of an emitter of radiance 1, nothing else: camera rays pass
    // it with probability 0.75, so the image converges to 0.75; a MASK cut-out (alpha below the cutoff) shows
    // the emitter behind it whole.
    for (const AlphaMode mode : {AlphaMode::Blend, AlphaMode::Mask}) {
        Scene scene;
        Material lamp = lambertian(0.0f);
        lamp.emission = glm::vec3(1.0f);
        scene.materials.push_back(lamp);
        addFlatQuad(scene, {-1.0f, -1.0f, -0.5f}, {2.0f, -1.0f, -0.5f}, {2.0f, 2.0f, -0.5f}, {-1.0f, 2.0f, -0.5f}, 0);
        Material black = lambertian(0.0f);
        black.baseColor.a = 0.25f;
        black.alphaMode = mode;
        RenderSettings settings = litOnly(16);
        settings.samplesPerPixel = 64;
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, black, settings);
        for (const Image* image : {&gpu.image, &cpu.image}) {
            if (mode == AlphaMode::Mask) {
                EXPECT_NEAR(image->at(8, 8).x, 1.0, 1e-6);
            } else {
                EXPECT_NEAR(meanRed(*image), 0.75, 0.005);
            }
        }
    }
}

TEST_F(GpuSurfaces, RaysThroughAHoleMeetTheFaceCoincidentWithIt) {
    // A leaf made of two coincident faces, the first all hole (MASK, alpha 0), the second opaque (albedo
    // 0.6), on a slanted plane, in front of the unit square (0.25), under ambient light 1 (paths: lit by the
    // background's 0.25 alone): rays pass the hole and meet the second face, which shows 0.6 (0.15) in every
    // pixel, whichever way the second face is wound and divided into triangles (the same triangle twice is
    // removed as a duplicate when the scene is built). The walk past the hole searched on from the hole's
    // distance, and missed the second face wherever rounding put it at or before that distance: in all 1024
    // pixels on the CPU, and in 1005 to 1019 of them on the GPU.
    const auto [a, b, c, d] = slantedSquare(-0.5f, 1.5f, 0.5f, {0.13f, 0.071f});
    struct Face {
        const char* name;
        std::array<glm::vec3, 4> corners;
    };
    for (const Face& face : {Face{"turned", {a, d, c, b}}, Face{"divided the other way", {b, c, d, a}},
                             Face{"turned and divided the other way", {b, a, d, c}}}) {
        for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
            SCOPED_TRACE(testing::Message()
                         << (integrator == Integrator::Path ? "paths, " : "Whitted, ") << face.name);
            Scene scene;
            scene.materials.push_back(allHole());
            Material leaf = lambertian(0.6f);
            leaf.doubleSided = true;
            scene.materials.push_back(leaf);
            addFlatQuad(scene, a, b, c, d, 0);
            addFlatQuad(scene, face.corners[0], face.corners[1], face.corners[2], face.corners[3], 1);
            RenderSettings settings = ambientOnly(32);
            settings.integrator = integrator;
            const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(0.25f), settings);
            for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}}) {
                const float expected = integrator == Integrator::Path ? 0.6f * 0.25f : 0.6f;
                int missed = 0;
                for (int y = 0; y < image->height; ++y)
                    for (int x = 0; x < image->width; ++x)
                        missed += std::abs(image->at(x, y).x - expected) > 1e-5f;
                EXPECT_EQ(missed, 0) << device;
            }
        }
    }
}

TEST_F(GpuSurfaces, RaysMeetEveryPrimitiveOfALeafAfterASolid) {
    // Two thin boxes of the same width (VKRT_shapes), one just above the other, filling the square camera's
    // view: the lower (albedo 0.3) comes first in their leaf of the tree, the upper (0.6) after it. Under
    // ambient light 1 (paths: the background's 0.25 alone) every pixel shows the upper box: 0.6 (0.15). The
    // GPU's walks visit a leaf's solids in their outer loop and go on with the rest of the leaf in the next
    // pass; a walk that dropped the rest saw the lower box.
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        SCOPED_TRACE(integrator == Integrator::Path ? "paths" : "Whitted");
        Scene scene;
        scene.materials.push_back(lambertian(0.3f));
        scene.materials.push_back(lambertian(0.6f));
        for (uint32_t box : {0u, 1u}) {
            const glm::dmat4 map =
                glm::scale(glm::translate(glm::dmat4(1.0), {0.5, 0.5, box == 0u ? -0.03 : 0.0}),
                           glm::dvec3(1.0, 1.0, 0.01));
            addSolid(scene, {makeShape(VKRT_SHAPE_BOX, box, map)}, {2u, 0u, 0u, 0u, 0u, 0u, 0u, 0u});
        }
        finalizeScene(scene);
        const FlatBvh bvh = test::bvhFor(scene);
        ASSERT_EQ(bvh.primIndices, (std::vector<uint32_t>{0u, 1u}));  // one leaf: the lower box first
        ASSERT_EQ(bvh.nodes[0].primCount, 2u);
        RenderSettings settings = ambientOnly(16);
        settings.integrator = integrator;
        const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, bvh, test::squareCamera(), settings,
                                                      test::shaderCacheDir());
        const float expected = integrator == Integrator::Path ? 0.6f * 0.25f : 0.6f;
        for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}}) {
            int missed = 0;
            for (int y = 0; y < image->height; ++y)
                for (int x = 0; x < image->width; ++x)
                    missed += std::abs(image->at(x, y).x - expected) > 1e-5f;
            EXPECT_EQ(missed, 0) << device;
        }
    }
}

TEST_F(GpuSurfaces, TwoCoincidentBlendFacesAreEachCrossedOnce) {
    // Two black faces of alpha 0.5 (BLEND) on one slanted plane, the second turned and divided into triangles
    // the other way, in front of an emitter of radiance 1: a camera ray passes each with probability 0.5, so
    // the image converges to 0.25. One face missed gives 0.5; one crossed twice, 0.125.
    const auto [a, b, c, d] = slantedSquare(-0.5f, 1.5f, 0.5f, {0.13f, 0.071f});
    Scene scene;
    Material black = lambertian(0.0f);
    black.baseColor.a = 0.5f;
    black.alphaMode = AlphaMode::Blend;
    black.doubleSided = true;
    scene.materials.push_back(black);
    addFlatQuad(scene, a, b, c, d, 0);
    addFlatQuad(scene, b, a, d, c, 0);
    Material lamp = lambertian(0.0f);
    lamp.emission = glm::vec3(1.0f);
    RenderSettings settings = litOnly(16);
    settings.samplesPerPixel = 64;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lamp, settings);
    for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}})
        EXPECT_NEAR(meanRed(*image), 0.25, 0.01) << device;
}

TEST_F(GpuSurfaces, ShadowRaysCrossEveryPrimitiveOfALeafPastATexturedHole) {
    // The unit square (albedo 1) under a sun from straight above, and between them, out of the camera's view,
    // two coincident quads in one leaf of the tree: one a hole throughout by its texture's alpha (MASK), the
    // other opaque, in either order. The square is black for both integrators. Where crossing a surface is
    // costly (here: textures), the GPU's shadow walk crosses a leaf's first candidate in its outer loop and
    // goes on with the rest of the leaf in the next pass; a walk that dropped the rest saw the sun through
    // the hole.
    for (const bool holeFirst : {true, false}) {
        SCOPED_TRACE(holeFirst ? "hole first" : "opaque first");
        Scene scene;
        scene.textures.push_back(textureOf(1, 1, {0x00ffffffu}));
        Material hole = lambertian(1.0f);
        hole.alphaMode = AlphaMode::Mask;
        hole.baseColorTexture.texture = 0;
        Material opaque = lambertian(0.0f);
        opaque.doubleSided = true;
        scene.materials =
            holeFirst ? std::vector<Material>{hole, opaque} : std::vector<Material>{opaque, hole};
        // The second divided along the other diagonal (a duplicate triangle would be removed).
        const glm::vec3 a(-1.0f, -1.0f, 1.2f), b(2.0f, -1.0f, 1.2f), c(2.0f, 2.0f, 1.2f),
            d(-1.0f, 2.0f, 1.2f);
        addFlatQuad(scene, a, b, c, d, 0);
        addFlatQuad(scene, b, c, d, a, 1);
        scene.lights.push_back(sunFrom({0.0, 0.0, 1.0}, float(M_PI)));
        for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
            SCOPED_TRACE(integrator == Integrator::Path ? "paths" : "Whitted");
            RenderSettings settings = litOnly(16);
            settings.integrator = integrator;
            settings.maxDepth = 0;
            const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(1.0f), settings);
            for (const auto& [image, device] : {std::pair{&gpu.image, "GPU"}, std::pair{&cpu.image, "CPU"}}) {
                SCOPED_TRACE(device);
                EXPECT_EQ(meanRed(*image), 0.0);
            }
        }
    }
}

TEST_F(GpuSurfaces, ShadowRaysPassAlphaHoles) {
    // A floor (the unit square, albedo 0.5) lit by a sun at 45 degrees; a blocker at height 0.5, out of the
    // camera's view (x from 1.2 to 3), casts its shadow on the floor's strip x > 0.7. The shadowed floor gets
    // 1 - coverage of the light: all of it through a MASK hole (alpha 0.4, cutoff 0.5), 0.6 of it through
    // BLEND alpha 0.4, none through an opaque blocker.
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(1.0, 0.0, 1.0));
    const double albedo = 0.5, illuminance = 2.0;
    const double lit = albedo / M_PI * illuminance * toLight.z;
    struct Case {
        AlphaMode mode;
        double passes;
    };
    for (const Case c : {Case{AlphaMode::Mask, 1.0}, Case{AlphaMode::Blend, 0.6}, Case{AlphaMode::Opaque, 0.0}}) {
        SCOPED_TRACE(testing::Message() << "alpha mode " << static_cast<int>(c.mode));
        Scene scene;
        scene.lights.push_back(sunFrom(toLight, static_cast<float>(illuminance)));
        Material blocker = lambertian(1.0f);
        blocker.baseColor.a = 0.4f;
        blocker.alphaMode = c.mode;
        blocker.doubleSided = true;
        scene.materials.push_back(blocker);
        addFlatQuad(scene, {1.2f, -1.0f, 0.5f}, {3.0f, -1.0f, 0.5f}, {3.0f, 2.0f, 0.5f}, {1.2f, 2.0f, 0.5f}, 0);
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, lambertian(static_cast<float>(albedo)),
                                                       litOnly(20));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_NEAR(image->at(4, 10).x, lit, 1e-6);               // x = 0.225: in the sun
            EXPECT_NEAR(image->at(17, 10).x, c.passes * lit, 1e-6);  // x = 0.875: behind the blocker
        }
    }
}

TEST_F(GpuSurfaces, UnlitShowsItsBaseColour) {
    // KHR_materials_unlit: the base colour times its texture is the radiance, whatever the lights and the
    // ambient term; the second texel of the texture halves it.
    Scene scene;
    scene.textures.push_back(textureOf(2, 1, {0xffffffffu, 0xff808080u}));
    scene.lights.push_back(sunFrom(glm::normalize(glm::dvec3(0.3, 0.2, 1.0)), 5.0f));
    Material material = lambertian(1.0f);
    material.baseColor = glm::vec4(0.3f, 0.6f, 0.9f, 1.0f);
    material.baseColorTexture.texture = 0;
    material.unlit = true;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(16));
    const double half = std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4);  // sRGB 128, decoded
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(image->at(3, 8).x, 0.3, 1e-6);
        EXPECT_NEAR(image->at(3, 8).y, 0.6, 1e-6);
        EXPECT_NEAR(image->at(3, 8).z, 0.9, 1e-6);
        EXPECT_NEAR(image->at(12, 8).z, 0.9 * half, 1e-6);
    }
}

TEST_F(GpuSurfaces, TransmissionTextureMultipliesTheFactor) {
    // A thin-walled surface of index 1 (no reflection), transmission factor 1 under a texture whose red is 0
    // on the left and 1 on the right: the left is an opaque white Lambertian surface (ambient 1 shows 1), the
    // right lets the background (0.25) straight through.
    Scene scene;
    scene.textures.push_back(textureOf(2, 1, {0xff000000u, 0xff0000ffu}));
    Material material = lambertian(1.0f);
    material.ior = 1.0f;
    material.transmission = 1.0f;
    material.transmissionTexture.texture = 0;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(16));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(image->at(3, 8).x, 1.0, 1e-6);
        EXPECT_NEAR(image->at(12, 8).x, 0.25, 1e-6);
    }
}

TEST_F(GpuSurfaces, ClearcoatDimsTheBaseAndReflects) {
    // A mirror-smooth coat (F0 0.04) of weight c over a Lambertian base, seen head-on: under a sun from
    // toLight, the base shows albedo / pi * E * cos scaled by 1 - c F(1) = 1 - 0.04 c (a delta lobe reflects no
    // sun); over a black base with a white background and nothing else, the coat's mirror shows 0.04 c. The
    // coat texture's red halves c on the right.
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
    const double albedo = 0.6, illuminance = 2.0, coat = 0.8;
    Scene scene;
    scene.textures.push_back(textureOf(2, 1, {0xffffffffu, 0xff000080u}));
    Material material = lambertian(static_cast<float>(albedo));
    material.clearcoat = static_cast<float>(coat);
    material.clearcoatTexture.texture = 0;
    const double half = 128.0 / 255.0;
    {
        Scene lit = scene;
        lit.lights.push_back(sunFrom(toLight, static_cast<float>(illuminance)));
        const auto [gpu, cpu] = test::renderUnitSquare(context(), lit, material, litOnly(16));
        const double base = albedo / M_PI * illuminance * toLight.z;
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_NEAR(image->at(3, 8).x, base * (1.0 - 0.04 * coat), 1e-6);
            EXPECT_NEAR(image->at(12, 8).x, base * (1.0 - 0.04 * coat * half), 1e-6);
        }
    }
    material.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    RenderSettings settings = litOnly(16);
    settings.background = glm::dvec3(1.0);
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, settings);
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(image->at(3, 8).x, 0.04 * coat, 1e-6);
        EXPECT_NEAR(image->at(12, 8).x, 0.04 * coat * half, 1e-6);
    }
}

TEST_F(GpuSurfaces, SheenNearGrazingReflectsNoMoreThanItReceives) {
    // A white sheen of roughness 0 over a black base, seen 1 degree from grazing in a white furnace, path
    // traced: the fitted shadowing makes its lobe's integral 1.4 there (1.6 at grazing), and the lobe divided
    // by it reflects all the light it receives, no more (1.4 before; 1.047 with the table's entries evenly
    // spaced in cos, now 1.009). The image's mean, against the table's interpolation and the noise of 64
    // samples in each of 256 pixels.
    Scene scene;
    Material material = lambertian(0.0f);
    material.sheenColor = glm::vec3(1.0f);
    material.sheenRoughness = 0.0f;
    scene.materials.push_back(material);
    addFlatQuad(scene, {-500.0f, -500.0f, 0.0f}, {500.0f, -500.0f, 0.0f}, {500.0f, 500.0f, 0.0f},
                {-500.0f, 500.0f, 0.0f}, 0);
    finalizeScene(scene);
    const double elevation = 1.0 * M_PI / 180.0;
    Camera camera = test::squareCamera();
    camera.forward = {0.0, std::cos(elevation), -std::sin(elevation)};
    camera.up = {0.0, std::sin(elevation), std::cos(elevation)};
    camera.position = -50.0 * camera.forward;
    camera.xmag = camera.ymag = 1.0;
    RenderSettings settings = ambientOnly(16);
    settings.integrator = Integrator::Path;
    settings.samplesPerPixel = 64;
    settings.background = glm::dvec3(1.0);
    const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, test::bvhFor(scene), camera, settings,
                                                  test::shaderCacheDir());
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(meanRed(*image), 1.0, 0.02);
    }
}

TEST_F(GpuSurfaces, SheenReflectsItsAlbedoAndConservesEnergy) {
    // KHR_materials_sheen over a black base, seen head-on under ambient 1: the sheen's directional albedo
    // E(1, r) times its colour, where E, interpolated from the table, is within 3% of a finer integration of the
    // Charlie lobe; under a sun, the lobe itself: colour x D x V x E cos, D and V (with Estevez and Kulla's
    // fitted shadowing) written out here. Over a white
    // Lambertian base the ambient image is exactly 1: the sheen takes from the base what it reflects.
    const double roughness = 0.37;
    const glm::dvec3 colour(1.0, 0.5, 0.25);
    const double albedo = shading::sheenAlbedoIntegral(1.0, roughness, 400);
    EXPECT_GT(albedo, 0.005);
    // Energy: from cos 2/31 on no entry reflects more than arrives (closer to grazing the fitted shadowing's
    // smoothest sheens reach 1.6: SheenNearGrazingReflectsNoMoreThanItReceives).
    const std::vector<float>& table = sheenAlbedoTable();
    for (size_t entry = 0; entry < table.size(); ++entry) {
        EXPECT_GE(table[entry], 0.0f);
        const double root = static_cast<double>(entry % VKRT_SHEEN_TABLE_SIZE) / (VKRT_SHEEN_TABLE_SIZE - 1);
        EXPECT_LE(table[entry], root * root < 2.0 / 31.0 ? 1.7f : 0.999f) << entry;
    }
    Material material = lambertian(0.0f);
    material.sheenColor = glm::vec3(colour);
    material.sheenRoughness = static_cast<float>(roughness);
    {
        const auto [gpu, cpu] = test::renderUnitSquare(context(), Scene{}, material, ambientOnly(8));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            // Between the table's entries, within 3% of the finer integral.
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(image->at(4, 4)[c], colour[c] * albedo, 0.03 * colour[c] * albedo);
        }
    }
    {
        const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.6, 0.1, 0.5));
        Scene scene;
        scene.lights.push_back(sunFrom(toLight, 2.0f));
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, litOnly(8));
        const double alpha = roughness * roughness, cosL = toLight.z;
        const double cosH = glm::normalize(toLight + glm::dvec3(0, 0, 1)).z;
        const double d = (2.0 + 1.0 / alpha) * std::pow(1.0 - cosH * cosH, 0.5 / alpha) / (2.0 * M_PI);
        // Estevez and Kulla's fitted Lambda: at cos 1 it mirrors the fit at 0.
        auto fit = [&](double x) {
            const double t = (1.0 - alpha) * (1.0 - alpha);
            return (21.5473 + t * (25.3245 - 21.5473)) / (1.0 + (3.82987 + t * (3.32435 - 3.82987)) *
                                                                    std::pow(x, 0.19823 + t * (0.16801 - 0.19823))) +
                   (-1.97760 + t * (-1.27393 + 1.97760)) * x + (-4.32054 + t * (-4.85967 + 4.32054));
        };
        auto lambda = [&](double c) {
            return c < 0.5 ? std::exp(fit(c)) : std::exp(2.0 * fit(0.5) - fit(1.0 - c));
        };
        const double v = 1.0 / (1.0 + lambda(1.0) + lambda(cosL)) / (4.0 * cosL);
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_NEAR(image->at(4, 4).x, d * v * 2.0 * cosL, 1e-5);
        }
    }
    material.baseColor = glm::vec4(1.0f);
    material.sheenColor = glm::vec3(1.0f);
    const auto [gpu, cpu] = test::renderUnitSquare(context(), Scene{}, material, ambientOnly(8));
    for (const Image* image : {&gpu.image, &cpu.image}) EXPECT_NEAR(image->at(4, 4).x, 1.0, 1e-5);
}

TEST_F(GpuSurfaces, ClearcoatDimsEmission) {
    // KHR_materials_clearcoat ("Emission"): an emitter of radiance 1 under a coat of weight 0.5, seen head-on,
    // sends out 1 - 0.5 F(1) = 0.98 (black base, black background, nothing else).
    Material material = lambertian(0.0f);
    material.emission = glm::vec3(1.0f);
    material.clearcoat = 0.5f;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), Scene{}, material, litOnly(8));
    for (const Image* image : {&gpu.image, &cpu.image}) EXPECT_NEAR(image->at(4, 4).x, 1.0 - 0.5 * 0.04, 1e-6);
}

// A 64x64 texture of black and white squares `block` texels wide.
Texture checkerTexture(int block) {
    std::vector<uint32_t> texels;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) texels.push_back(((x / block + y / block) % 2 == 0) ? 0xffffffffu : 0xff000000u);
    }
    return textureOf(64, 64, texels);
}

TEST_F(GpuSurfaces, RayConesPickTheMipmapLevel) {
    // The unit square seen head-on by an orthographic camera of n x n pixels: each camera ray's cone is
    // 1/n wide, the square has one texture coordinate per world unit, so a 64-texel texture is seen at level
    // of detail log2(64 / n). Squares of 4 texels are single texels at level 2 and grey (sRGB 188: the mean
    // of black and white as linear light, encoded) at level 3: 16 pixels show the checker exactly, 8 pixels
    // grey, with the nearest level and texel (NEAREST_MIPMAP_NEAREST). A one-texel checker without mipmaps
    // (NEAREST) aliases: 4 jittered samples per pixel give pixels far from grey.
    const double grey = std::pow((188.0 / 255.0 + 0.055) / 1.055, 2.4);
    Material material = lambertian(1.0f);
    material.ior = 1.0f;  // no specular: the albedo alone under ambient 1
    material.baseColorTexture.texture = 0;
    Scene scene;
    scene.textures.push_back(checkerTexture(4));
    scene.textures[0].minNearest = true;
    scene.textures[0].mipmaps = MipmapMode::Nearest;
    for (const int size : {16, 8}) {
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(size));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            for (int y = 0; y < size; ++y) {
                for (int x = 0; x < size; ++x) {
                    const double expected = size == 16 ? ((x + y) % 2 == 0 ? 1.0 : 0.0) : grey;
                    ASSERT_NEAR(image->at(x, y).x, expected, 1e-5) << size << " pixels, at " << x << ", " << y;
                }
            }
        }
    }
    // A negative ymag (glTF: SHOULD NOT, yet valid) turns the orthographic image upside down and leaves the
    // cones as wide: the same grey at 8 pixels (the cone's negative width once chose no level: the checker
    // aliased).
    Scene flipped = scene;
    flipped.materials.push_back(material);
    test::addUnitSquare(flipped, 0);
    finalizeScene(flipped);
    Camera upsideDown = test::squareCamera();
    upsideDown.ymag = -upsideDown.ymag;
    const test::RenderPair turned = test::renderGpuAndCpu(context(), flipped, test::bvhFor(flipped),
                                                          upsideDown, ambientOnly(8), test::shaderCacheDir());
    for (const Image* image : {&turned.gpu.image, &turned.cpu.image}) {
        for (const glm::vec3& pixel : image->pixels) ASSERT_NEAR(pixel.x, grey, 1e-5) << "ymag < 0";
    }
    scene.textures[0] = checkerTexture(1);
    scene.textures[0].minNearest = true;
    scene.textures[0].mipmaps = MipmapMode::None;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(16));
    int far = 0;
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) far += std::abs(cpu.image.at(x, y).x - 0.5) > 0.2 ? 1 : 0;
    }
    EXPECT_GT(far, 32);
    test::expectMatchesReference(gpu.image, cpu.image, "no-mipmaps");
}

TEST_F(GpuSurfaces, ATextureSharedByColourAndDataKeepsEachMeaningInItsMipmaps) {
    // A one-texel checker read as occlusion (linear data) at level 3 (8 pixels across 64 texels) is 0.5 (128
    // / 255 as its byte holds it): the mean of 0 and 1. Shared with another material's base colour (sRGB), it
    // once got one mip chain averaged as colours and encoded, and occlusion read byte 188 as 0.737.
    Material occluded = lambertian(1.0f);
    occluded.ior = 1.0f;  // no specular layer: albedo 1 times occlusion under ambient 1
    occluded.occlusionTexture.texture = 0;
    for (const bool shared : {false, true}) {
        Scene scene;
        scene.textures.push_back(checkerTexture(1));
        scene.textures[0].minNearest = true;
        scene.textures[0].mipmaps = MipmapMode::Nearest;
        if (shared) {
            Material painted = lambertian(1.0f);
            painted.baseColorTexture.texture = 0;
            scene.materials.push_back(painted);  // on no surface: it only shares the texture
        }
        const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, occluded, ambientOnly(8));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            for (const glm::vec3& pixel : image->pixels) {
                ASSERT_NEAR(pixel.x, 128.0 / 255.0, 1e-5)
                    << (shared ? "shared" : "alone") << (image == &gpu.image ? " gpu" : " cpu");
            }
        }
    }
}

TEST_F(GpuSurfaces, TrilinearFilteringBlendsLevels) {
    // Between levels: at 12 pixels the level of detail is log2(64 / 12) = 2.415, so LINEAR_MIPMAP_LINEAR
    // blends level 2 (the checker of single texels, bilinear) with level 3 (uniform grey): the image's mean
    // stays the checker's mean, and no pixel reaches black or white. Both devices agree.
    Material material = lambertian(1.0f);
    material.ior = 1.0f;
    material.baseColorTexture.texture = 0;
    Scene scene;
    scene.textures.push_back(checkerTexture(4));
    scene.textures[0].nearest = false;
    const auto [gpu, cpu] = test::renderUnitSquare(context(), scene, material, ambientOnly(12));
    double sum = 0.0, lowest = 1.0, highest = 0.0;
    for (int y = 0; y < 12; ++y) {
        for (int x = 0; x < 12; ++x) {
            const double value = cpu.image.at(x, y).x;
            sum += value;
            lowest = std::min(lowest, value);
            highest = std::max(highest, value);
        }
    }
    EXPECT_NEAR(sum / 144.0, 0.5, 0.03);
    EXPECT_GT(lowest, 0.05);
    EXPECT_LT(highest, 0.95);
    test::expectMatchesReference(gpu.image, cpu.image, "trilinear");
}

TEST_F(GpuSurfaces, FeaturesFollowWhatMaterialsUse) {
    // Vertex normals are compiled in where one is not its face's normal, however slightly (1e-3 radians turn
    // a mirror's reflection by 2e-3); alpha only where some surface can have a hole; normal maps only where a
    // normal-mapped material meets a tangent frame or a sphere or shape, which makes its own; levels of
    // detail only where a texture has levels or another filter when minified; unlit, clear coat and sheen
    // where a material has them.
    Scene scene;
    Material material = lambertian(1.0f);
    material.alphaMode = AlphaMode::Blend;  // alpha 1 everywhere: no holes
    scene.materials.push_back(material);
    test::addUnitSquare(scene, 0);
    finalizeScene(scene);
    EXPECT_FALSE(detectFeatures(scene).smoothNormals);
    Scene tilted = scene;
    tilted.shading[0].normal[0] = glm::vec3(0.0f, std::sin(1e-3f), std::cos(1e-3f));
    EXPECT_TRUE(detectFeatures(tilted).smoothNormals);
    // A file's flat normals rounded to floats (a Cornell box's are up to 5e-5 radians off) stay flat.
    tilted.shading[0].normal[0] = glm::vec3(0.0f, std::sin(5e-5f), std::cos(5e-5f));
    EXPECT_FALSE(detectFeatures(tilted).smoothNormals);
    EXPECT_FALSE(detectFeatures(scene).alpha);
    scene.materials[0].alphaMode = AlphaMode::Mask;
    scene.materials[0].baseColor.a = 0.25f;  // below the cutoff: all hole
    EXPECT_TRUE(detectFeatures(scene).alpha);
    scene.materials[0].normalTexture.texture = 0;
    scene.textures.push_back(textureOf(1, 1, {normalTexel({0.0, 0.0, 1.0})}));
    EXPECT_FALSE(detectFeatures(scene).normalMaps);  // no triangle has a tangent frame
    Scene withSphere = scene;
    withSphere.spheres.push_back({glm::vec3(0.0f, 0.0f, -2.0f), 0.5f, 0});
    finalizeScene(withSphere);
    EXPECT_TRUE(detectFeatures(withSphere).normalMaps);  // a sphere makes its own frame
    // A triangle 1024 times as long as the smallest sphere takes its hit distance again in double.
    EXPECT_FALSE(detectFeatures(withSphere).largeTriangles);
    // ... at any pose of its motion: the square stretched 2048 times at the shutter's close.
    Scene stretched = withSphere;
    stretched.motionSegments = 1;
    for (const Triangle& t : withSphere.triangles)
        stretched.trianglePoses.push_back({t.v0 * 2048.0f, t.v1 * 2048.0f, t.v2 * 2048.0f, t.material});
    stretched.spherePoses = withSphere.spheres;
    finalizeScene(stretched);
    EXPECT_TRUE(detectFeatures(stretched).largeTriangles);
    withSphere.spheres.push_back({glm::vec3(0.0f, 0.0f, -2.0f), 5e-4f, 0});
    finalizeScene(withSphere);
    EXPECT_TRUE(detectFeatures(withSphere).largeTriangles);
    // A sphere 1024 times as wide as the smallest primitive finds its roots in double.
    EXPECT_FALSE(detectFeatures(withSphere).largeSpheres);  // 1 against 1e-3 wide
    withSphere.spheres.push_back({glm::vec3(0.0f, 0.0f, -4.0f), 1.0f, 0});
    finalizeScene(withSphere);
    EXPECT_TRUE(detectFeatures(withSphere).largeSpheres);
    scene.tangents.assign(2, {});
    EXPECT_TRUE(detectFeatures(scene).normalMaps);
    // The 1x1 normal texture has no level below it and one filter: no level of detail to choose.
    EXPECT_FALSE(detectFeatures(scene).mipmaps);
    scene.textures[0] = textureOf(2, 2, std::vector<uint32_t>(4, normalTexel({0.0, 0.0, 1.0})));
    EXPECT_TRUE(detectFeatures(scene).mipmaps);
    scene.textures[0].mipmaps = MipmapMode::None;
    scene.textures[0].minNearest = true;  // nearest either way, no mipmaps
    EXPECT_FALSE(detectFeatures(scene).mipmaps);
    scene.textures[0].minNearest = false;  // magnified nearest, minified bilinear
    EXPECT_TRUE(detectFeatures(scene).mipmaps);
    // Unlit, coat and sheen each switch on their own code.
    const SceneFeatures before = detectFeatures(scene);
    EXPECT_FALSE(before.unlit || before.clearcoat || before.sheen);
    scene.materials[0].unlit = true;
    scene.materials[0].clearcoat = 0.5f;
    scene.materials[0].sheenColor = glm::vec3(0.2f);
    const SceneFeatures after = detectFeatures(scene);
    EXPECT_TRUE(after.unlit && after.clearcoat && after.sheen);
    // Beer's law only where a volume's light fades: a finite attenuation distance and a colour below 1.
    Material glass = lambertian(1.0f);
    glass.transmission = 1.0f;
    glass.thickness = 1.0f;
    scene.materials = {glass};
    EXPECT_TRUE(detectFeatures(scene).volumes);
    EXPECT_FALSE(detectFeatures(scene).absorption);  // attenuation distance infinite
    scene.materials[0].attenuationDistance = 0.5f;
    EXPECT_FALSE(detectFeatures(scene).absorption);  // attenuation colour white
    scene.materials[0].attenuationColor = glm::vec3(1.0f, 0.9f, 1.0f);
    EXPECT_TRUE(detectFeatures(scene).absorption);
    scene.materials[0].thickness = 0.0f;  // thin-walled: no volume to fade in
    EXPECT_FALSE(detectFeatures(scene).absorption);
}

}  // namespace
}  // namespace vkrt
