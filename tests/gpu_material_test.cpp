// Material inputs with known answers, on the GPU and the CPU reference alike: KHR_texture_transform scales
// and turns a checker, the metallic-roughness texture's blue and green channels multiply metallic and
// roughness, and the occlusion texture dims the ambient term alone.
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/scene_features.h"
#include "image/image_metrics.h"
#include "scene/camera_selection.h"
#include "scene/scene_builder.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"
#include "support/unit_square.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

using test::addUnitSquare;
using test::ambientOnly;
using test::lambertian;
using test::squareCamera;
using test::textureOf;

// The unit square in `scene` (which holds its textures and lights) with `material`, rendered on both devices.
class GpuMaterials : public Gpu {
  protected:
    static test::RenderPair renderSquare(const Scene& scene, const Material& material,
                                         const RenderSettings& settings) {
        return test::renderUnitSquare(context(), scene, material, settings);
    }
};

// A directional light shining along `direction` with illuminance `illuminance`.
PunctualLight sunAlong(glm::vec3 direction, double illuminance) {
    PunctualLight sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(direction);
    sun.intensity = static_cast<float>(illuminance);
    return sun;
}

// How many runs of bright and dark pixels a row crosses.
int cellsAlongRow(const Image& image, int y) {
    int cells = 1;
    bool bright = image.at(0, y).x > 0.5f;
    for (int x = 1; x < image.width; ++x) {
        const bool now = image.at(x, y).x > 0.5f;
        cells += now != bright ? 1 : 0;
        bright = now;
    }
    return cells;
}

// A scene holding a 2x2 white and black checker texture, and a material that shows it scaled by 4 (8 cells
// across and down the square) and moved by `offset`.
std::pair<Scene, Material> scaledChecker(float offset) {
    Scene scene;
    scene.textures.push_back(textureOf(2, 2, {0xffffffffu, 0xff000000u, 0xff000000u, 0xffffffffu}));
    Material checker;
    checker.metallic = 0.0f;
    checker.ior = 1.0f;  // no specular: the albedo alone
    checker.baseColorTexture.texture = 0;
    checker.baseColorTexture.scale = glm::vec2(4.0f);
    checker.baseColorTexture.offset = glm::vec2(offset);
    return {scene, checker};
}

TEST_F(GpuMaterials, TextureTransformScalesTheChecker) {
    // The scaled checker, the second time moved by one whole period of the texture, which must not show.
    for (const float offset : {0.0f, 1.0f}) {
        const auto [scene, checker] = scaledChecker(offset);
        const auto [gpu, cpu] = renderSquare(scene, checker, ambientOnly(64));
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_EQ(cellsAlongRow(*image, 4), 8);
            EXPECT_EQ(cellsAlongRow(*image, 37), 8);
            EXPECT_NEAR(image->at(3, 3).x, 1.0f, 1e-6f);  // the top-left texel is white
            EXPECT_NEAR(image->at(11, 3).x, 0.0f, 1e-6f);
        }
        test::expectMatchesReference(gpu.image, cpu.image, "texture-transform");
    }
}

TEST_F(GpuMaterials, TextureTransformRotatesAsTheSampleViewerDoes) {
    // One white texel of four, at (u, v) in [0, 0.5)^2, rotated by 90 degrees: uv' = (v, -u), as the Khronos
    // sample viewer applies KHR_texture_transform (TextureTransformTest checks itself with it). On the square
    // (uv = (x, 1 - y)) the white quarter lands where x > 0.5 and y > 0.5: the image's top right. The
    // transposed rotation would put it at the bottom left.
    Scene scene;
    scene.textures.push_back(textureOf(2, 2, {0xffffffffu, 0xff000000u, 0xff000000u, 0xff000000u}));
    Material quarter;
    quarter.metallic = 0.0f;
    quarter.ior = 1.0f;
    quarter.baseColorTexture.texture = 0;
    quarter.baseColorTexture.rotation = static_cast<float>(0.5 * M_PI);
    const auto [gpu, cpu] = renderSquare(scene, quarter, ambientOnly(16));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        EXPECT_NEAR(image->at(12, 3).x, 1.0f, 1e-6f);  // top right
        EXPECT_NEAR(image->at(3, 12).x, 0.0f, 1e-6f);  // bottom left
        EXPECT_NEAR(image->at(3, 3).x, 0.0f, 1e-6f);
        EXPECT_NEAR(image->at(12, 12).x, 0.0f, 1e-6f);
    }
}

TEST_F(GpuMaterials, TextureCoordinatesFarFromTheImageReadItSafely) {
    // The checker of TextureTransformScalesTheChecker moved by whole periods, 2^16 and 2^30: both devices
    // show it unmoved. The offset is taken modulo 2 when the material is packed: in single precision 4u +
    // 2^16 keeps 7 bits of u's fraction and 4u + 2^30 none (its unit in the last place is 128), so the GPU
    // read texels displaced, or every pixel the one coordinate 0.
    const auto [scene, unmovedChecker] = scaledChecker(0.0f);
    const auto unmoved = renderSquare(scene, unmovedChecker, ambientOnly(64));
    for (const float offset : {65536.0f, 1073741824.0f}) {
        const auto [gpu, cpu] = renderSquare(scene, scaledChecker(offset).second, ambientOnly(64));
        EXPECT_EQ(compareImages(cpu.image, unmoved.cpu.image, 0.0, 1e-4).fractionOff, 0.0) << offset;
        EXPECT_EQ(compareImages(gpu.image, unmoved.gpu.image, 0.0, 1e-4).fractionOff, 0.0) << offset;
    }
    // Scaled by 2^32: texel positions beyond an int (undefined; the CPU read the wrong texels) are brought
    // near the image before they are read. Every pixel's footprint covers the whole texture: its last mipmap
    // level.
    Material far = unmovedChecker;
    far.baseColorTexture.scale = glm::vec2(4294967296.0f);
    const auto [gpu, cpu] = renderSquare(scene, far, ambientOnly(64));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        const glm::vec3 first = image->at(0, 0);
        for (int y = 0; y < image->height; y += 7) {
            for (int x = 0; x < image->width; x += 7) EXPECT_EQ(image->at(x, y), first) << x << ", " << y;
        }
        EXPECT_TRUE(first.x >= 0.0f && first.x <= 1.0f) << first.x;
    }
}

// A lamp 1 x 1 at height 1, facing down, whose emission and alpha are a 64 x 64 checker (mipmapped,
// bilinear): white cells lit and covered, the others dark and cut out (MASK) or clear (BLEND); a glossy metal
// floor below.
Scene cutOutLampScene(AlphaMode alphaMode) {
    Scene scene;
    std::vector<uint32_t> texels;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) texels.push_back((x / 8 + y / 8) % 2 == 0 ? 0xffffffffu : 0x000a0a0au);
    }
    Texture checker = textureOf(64, 64, texels);
    checker.nearest = false;
    scene.textures.push_back(checker);
    Material floor;
    floor.metallic = 1.0f;
    floor.roughness = 0.2f;
    floor.doubleSided = true;
    scene.materials.push_back(floor);
    Material lamp = lambertian(0.0f);
    lamp.baseColorTexture.texture = 0;
    lamp.alphaMode = alphaMode;
    lamp.emission = glm::vec3(1.0f);
    lamp.emissiveTexture.texture = 0;
    lamp.doubleSided = true;
    scene.materials.push_back(lamp);
    addFlatQuad(scene, {-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}, 0);
    addFlatQuad(scene, {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}, 1);
    for (size_t i = scene.triangles.size() - 2; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 v = k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2;
            scene.shading[i].uv[k] = glm::vec2(v.x + 0.5f, v.z + 0.5f);
        }
    }
    finalizeScene(scene);
    return scene;
}

using test::meanRed;

TEST_F(GpuMaterials, CutOutLampsLightAlikeWithAndWithoutMultipleImportanceSampling) {
    // Seen in the floor from between it and the lamp, 32 x 32 pixels: a bounce ray's cone there spans several
    // texels. The emission a bounce ray met was read at its cone's mip level, while light samples, the
    // MASK test and an emitter's coverage read level 0, so the two strategies weighed different lamps: with
    // multiple importance sampling this image was 13% (MASK) and 17% (BLEND) darker than with light samples
    // alone (0.870 and 0.828; now within 0.3%). The same for a camera looking straight at the lamp: its mean
    // must not depend on the resolution (16 x 16 against 128 x 128 was 0.829 and 0.776; now within 0.03%).
    for (const AlphaMode mode : {AlphaMode::Mask, AlphaMode::Blend}) {
        SCOPED_TRACE(mode == AlphaMode::Mask ? "MASK" : "BLEND");
        const Scene scene = cutOutLampScene(mode);
        const FlatBvh bvh = test::bvhFor(scene);
        Camera down;
        down.position = {0.0, 0.5, 0.0};
        down.forward = {0.0, -1.0, 0.0};
        down.up = {0.0, 0.0, -1.0};
        down.right = {1.0, 0.0, 0.0};
        down.yfov = M_PI / 3.0;
        RenderSettings settings;
        settings.integrator = Integrator::Path;
        settings.maxDepth = 1;
        settings.width = settings.height = 32;
        settings.samplesPerPixel = 512;
        const auto weighed =
            test::renderGpuAndCpu(context(), scene, bvh, down, settings, test::shaderCacheDir());
        settings.multipleImportanceSampling = false;
        const auto sampled =
            test::renderGpuAndCpu(context(), scene, bvh, down, settings, test::shaderCacheDir());
        EXPECT_NEAR(meanRed(weighed.cpu.image) / meanRed(sampled.cpu.image), 1.0, 0.03);
        EXPECT_NEAR(meanRed(weighed.gpu.image) / meanRed(sampled.gpu.image), 1.0, 0.03);
        EXPECT_NEAR(meanRed(weighed.gpu.image) / meanRed(weighed.cpu.image), 1.0, 0.01);

        Camera up = down;
        up.position = {0.0, 0.2, 0.0};
        up.forward = {0.0, 1.0, 0.0};
        up.up = {0.0, 0.0, 1.0};
        up.yfov = 1.0;
        RenderSettings coarse;
        coarse.width = coarse.height = 16;
        coarse.samplesPerPixel = 64;
        coarse.ambient = glm::dvec3(0.0);
        RenderSettings fine = coarse;
        fine.width = fine.height = 128;
        fine.samplesPerPixel = 1;
        const auto small = test::renderGpuAndCpu(context(), scene, bvh, up, coarse, test::shaderCacheDir());
        const auto large = test::renderGpuAndCpu(context(), scene, bvh, up, fine, test::shaderCacheDir());
        EXPECT_NEAR(meanRed(small.cpu.image) / meanRed(large.cpu.image), 1.0, 0.02);
        EXPECT_NEAR(meanRed(small.gpu.image) / meanRed(large.gpu.image), 1.0, 0.02);
    }
}

// A lamp does not light itself through its own plane. A double-sided emissive quad of two triangles, tilted
// so that its corners round off the plane, filling the view: every light sample that picks the triangle the
// point is not on lies in the point's plane, where both cosines are 0 but for rounding, whose signs decided
// whether a shadow ray was traced, differently on each device (an emissive floor of a random scene: 1,353
// shadow rays on the GPU against 2,082 on the CPU, the same image). Now neither traces one, and the lamp
// shows its emission alone (Whitted, no ambient term).
TEST_F(GpuMaterials, ALampDoesNotLightItselfThroughItsOwnPlane) {
    Scene scene;
    Material lamp = lambertian(0.5f);
    lamp.emission = glm::vec3(0.7f);
    lamp.doubleSided = true;
    scene.materials.push_back(lamp);
    // The plane y = 0.3 x + 0.2 z.
    const auto at = [](float x, float z) { return glm::vec3(x, 0.3f * x + 0.2f * z, z); };
    addFlatQuad(scene, at(-1.0f, -1.0f), at(1.0f, -1.0f), at(1.0f, 1.0f), at(-1.0f, 1.0f), 0);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    Camera down;
    down.position = {0.0, 2.0, 0.0};
    down.forward = {0.0, -1.0, 0.0};
    down.up = {0.0, 0.0, -1.0};
    down.right = {1.0, 0.0, 0.0};
    down.yfov = 0.5;
    RenderSettings settings;
    settings.integrator = Integrator::Whitted;
    settings.ambient = glm::dvec3(0.0);
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 4;
    const auto both = test::renderGpuAndCpu(context(), scene, bvh, down, settings, test::shaderCacheDir());
    for (const RenderResult* r : {&both.gpu, &both.cpu}) {
        SCOPED_TRACE(r == &both.gpu ? "GPU" : "CPU");
        EXPECT_EQ(r->rays.shadow, 0u);
        for (const glm::vec3& p : r->image.pixels) ASSERT_NEAR(p.x, 0.7f, 1e-6f);
    }
}

TEST_F(GpuMaterials, LightFromInsideWaterIsDimmedByTheIndexSquaredOnTheWayOut) {
    // A slab of clear water (index 1.33, without reflection: KHR_materials_specular's factor 0) 2 deep;
    // inside it a point light of 10 cd at depth 0.5 over a white Lambertian floor at depth 1.5, seen straight
    // down from the air. The floor's radiance in the water is 10 / 1^2 / pi; radiance over the index squared
    // crosses the surface unchanged, so the air sees 1 / 1.33^2 of it. Without that factor it came out 1.33^2
    // times too bright.
    Scene scene;
    Material water = lambertian(1.0f);
    water.roughness = 0.0f;
    water.transmission = 1.0f;
    water.ior = 1.33f;
    water.thickness = 1.0f;
    scene.materials = {water, lambertian(1.0f)};
    const glm::vec3 corners[4] = {{-20, -20, 0}, {20, -20, 0}, {20, 20, 0}, {-20, 20, 0}};
    const glm::vec3 depth(0.0f, 0.0f, 2.0f);
    addFlatQuad(scene, corners[0], corners[1], corners[2], corners[3], 0);  // the surface, facing up
    addFlatQuad(scene, corners[3] - depth, corners[2] - depth, corners[1] - depth, corners[0] - depth, 0);
    addFlatQuad(scene, {-0.5f, -0.5f, -1.5f}, {0.5f, -0.5f, -1.5f}, {0.5f, 0.5f, -1.5f}, {-0.5f, 0.5f, -1.5f},
                1);
    PunctualLight lamp;
    lamp.position = {0.0, 0.0, -0.5};
    lamp.intensity = 10.0f;
    scene.lights.push_back(lamp);
    finalizeScene(scene);
    const FlatBvh bvh = test::bvhFor(scene);
    Camera down;
    down.projection = Projection::Orthographic;
    down.position = {0.0, 0.0, 3.0};
    down.forward = {0.0, 0.0, -1.0};
    down.xmag = down.ymag = 1e-3;  // the floor's irradiance falls by 2e-6 over the view
    const double expected = 10.0 / M_PI / (1.33 * 1.33);
    for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        SCOPED_TRACE(integratorName(integrator));
        RenderSettings settings;
        settings.integrator = integrator;
        settings.maxDepth = 1;  // the floor's direct light alone
        settings.width = settings.height = 4;
        settings.samplesPerPixel = 4;
        settings.ambient = glm::dvec3(0.0);
        const auto both =
            test::renderGpuAndCpu(context(), scene, bvh, down, settings, test::shaderCacheDir());
        EXPECT_NEAR(both.cpu.image.at(2, 2).x, expected, 1e-5 * expected);
        EXPECT_NEAR(both.gpu.image.at(2, 2).x, expected, 1e-5 * expected);
    }
}

TEST_F(GpuMaterials, MetallicRoughnessTextureMultipliesTheFactors) {
    // Metallic and roughness factors 1 under a texture whose blue channel is 0 make a dielectric, equal to
    // factors (0, 1) without a texture; green 0 and blue 1 make a mirror metal, equal to factors (1, 0).
    struct Case {
        uint32_t texel;  // RGBA8: green roughness, blue metallic
        float metallic, roughness;
    };
    for (const Case& c : {Case{0xff00ff00u, 0.0f, 1.0f}, Case{0xffff0000u, 1.0f, 0.0f}}) {
        Image images[2][2];  // [textured, factors][gpu, cpu]
        for (int textured = 0; textured < 2; ++textured) {
            Scene scene;
            scene.textures.push_back(textureOf(1, 1, {c.texel}));
            Material material;
            material.baseColor = glm::vec4(0.8f, 0.6f, 0.4f, 1.0f);
            if (textured == 0) {
                material.metallic = material.roughness = 1.0f;
                material.metallicRoughnessTexture.texture = 0;
            } else {
                material.metallic = c.metallic;
                material.roughness = c.roughness;
            }
            const auto [gpu, cpu] = renderSquare(scene, material, ambientOnly(16));
            images[textured][0] = gpu.image;
            images[textured][1] = cpu.image;
        }
        for (int device = 0; device < 2; ++device) {
            EXPECT_EQ(compareImages(images[0][device], images[1][device], 1e-6, 1e-7).fractionOff, 0.0)
                << "texture " << std::hex << c.texel << " on the " << (device == 0 ? "GPU" : "CPU");
        }
        // In the ambient light, the dielectric shows the 1 - F0 of its albedo that its specular layer leaves
        // it, plus F0 (0.04); the mirror metal reflects the background (0.25) with Schlick's F at normal
        // incidence, its base colour.
        const float expected = c.metallic == 0.0f ? 0.8f * (1.0f - 0.04f) + 0.04f : 0.25f * 0.8f;
        EXPECT_NEAR(images[0][1].at(8, 8).x, expected, 1e-5f);
        test::expectMatchesReference(images[0][0], images[0][1], "metallic-roughness-texture");
    }
}

TEST_F(GpuMaterials, ExtensionTexturesMultiplyTheirFactors) {
    // Each texture of KHR_materials_specular, _clearcoat and _sheen, and the emissive texture, is read from
    // its channel and multiplies its factor: a 1x1 texture whose channel holds t renders as the factor times
    // t without it (colour textures: the sRGB bytes 0 and 255, which decode exactly), while the texture's
    // other channels hold values that would show if read instead. Lit by a sun and the ambient term, both
    // devices, both integrators; and the texture changes the image (the case can fail).
    struct Case {
        const char* slot;
        uint32_t texel;                         // RGBA8, red in the lowest byte
        std::function<void(Material&)> factor;  // the factor the texture multiplies, set to 1 or a colour
        std::function<void(Material&)> scaled;  // that factor times the texel's value, without the texture
        TextureSlot Material::*texture;
    };
    constexpr float t = 64.0f / 255.0f;  // the byte 0x40, read linearly
    const std::vector<Case> cases = {
        {"specular (alpha)", 0x40ffffffu, [](Material& m) { m.specularFactor = 1.0f; },
         [&](Material& m) { m.specularFactor = t; }, &Material::specularTexture},
        {"specular colour (sRGB)", 0x00ff00ffu,
         [](Material& m) { m.specularColor = glm::vec3(0.5f, 0.8f, 1.0f); },
         [](Material& m) { m.specularColor = glm::vec3(0.5f, 0.0f, 1.0f); }, &Material::specularColorTexture},
        {"clearcoat roughness (green)", 0xffff40ffu, [](Material& m) { m.clearcoatRoughness = 1.0f; },
         [&](Material& m) { m.clearcoatRoughness = t; }, &Material::clearcoatRoughnessTexture},
        {"sheen colour (sRGB)", 0x0000ffffu, [](Material& m) { m.sheenColor = glm::vec3(1.0f, 0.6f, 0.3f); },
         [](Material& m) { m.sheenColor = glm::vec3(1.0f, 0.6f, 0.0f); }, &Material::sheenColorTexture},
        {"sheen roughness (alpha)", 0x40ffffffu, [](Material& m) { m.sheenRoughness = 1.0f; },
         [&](Material& m) { m.sheenRoughness = t; }, &Material::sheenRoughnessTexture},
        {"emission (sRGB)", 0x00ff00ffu, [](Material& m) { m.emission = glm::vec3(2.0f, 1.0f, 0.5f); },
         [](Material& m) { m.emission = glm::vec3(2.0f, 0.0f, 0.5f); }, &Material::emissiveTexture},
    };
    for (const Case& c : cases) {
        for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
            SCOPED_TRACE(std::string(c.slot) + (integrator == Integrator::Path ? ", paths" : ", Whitted"));
            Material material;  // a rough, coated, sheened dielectric: every slot above changes what it shows
            material.baseColor = glm::vec4(0.4f, 0.3f, 0.2f, 1.0f);
            material.metallic = 0.0f;
            material.roughness = 0.4f;
            material.clearcoat = 0.7f;
            material.clearcoatRoughness = 0.3f;
            material.sheenColor = glm::vec3(0.5f);
            material.sheenRoughness = 0.5f;
            Material textured = material, scaled = material, untextured = material;
            c.factor(textured);
            c.factor(untextured);
            textured.*c.texture = TextureSlot{};
            (textured.*c.texture).texture = 0;
            c.scaled(scaled);
            RenderSettings settings = ambientOnly(8);
            settings.integrator = integrator;
            Image images[3][2];  // [textured, scaled, factor alone][gpu, cpu]
            const Material* materials[3] = {&textured, &scaled, &untextured};
            for (int k = 0; k < 3; ++k) {
                Scene scene;
                scene.textures.push_back(textureOf(1, 1, {c.texel}));
                scene.lights.push_back(sunAlong(glm::vec3(0.3f, -0.2f, -1.0f), 2.0));
                const auto [gpu, cpu] = renderSquare(scene, *materials[k], settings);
                images[k][0] = gpu.image;
                images[k][1] = cpu.image;
            }
            for (int device = 0; device < 2; ++device) {
                EXPECT_EQ(compareImages(images[0][device], images[1][device], 1e-5, 1e-7).fractionOff, 0.0)
                    << (device == 0 ? "GPU" : "CPU") << ": the texture does not multiply its factor";
                EXPECT_GT(compareImages(images[0][device], images[2][device], 1e-3, 1e-6).fractionOff, 0.9)
                    << (device == 0 ? "GPU" : "CPU") << ": the texture changes nothing here";
            }
        }
    }
}

TEST_F(GpuMaterials, OcclusionTextureDimsOnlyTheAmbientTerm) {
    // A Lambertian square of albedo 0.8 in ambient radiance 1 shows 0.8 times the occlusion,
    // 1 + strength (red - 1); under a light alone (no ambient) occlusion changes nothing.
    const double red = 128.0 / 255.0;
    for (const float strength : {1.0f, 0.5f}) {
        for (const bool ambient : {true, false}) {
            Image images[2][2];  // [occluded, plain][gpu, cpu]
            for (int occluded = 0; occluded < 2; ++occluded) {
                Scene scene;
                scene.textures.push_back(textureOf(1, 1, {0xff000080u}));
                Material material;
                material.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
                material.metallic = 0.0f;
                material.ior = 1.0f;
                if (occluded == 0) {
                    material.occlusionTexture.texture = 0;
                    material.occlusionStrength = strength;
                }
                if (!ambient) scene.lights.push_back(sunAlong(glm::vec3(0.3f, -0.2f, -1.0f), 2.0));
                RenderSettings settings = ambientOnly(16);
                if (!ambient) settings.ambient = glm::dvec3(0.0);
                const auto [gpu, cpu] = renderSquare(scene, material, settings);
                images[occluded][0] = gpu.image;
                images[occluded][1] = cpu.image;
            }
            const double occlusion = ambient ? 1.0 + strength * (red - 1.0) : 1.0;
            for (int device = 0; device < 2; ++device) {
                EXPECT_NEAR(images[0][device].at(8, 8).x, occlusion * images[1][device].at(8, 8).x, 1e-5)
                    << "strength " << strength << (ambient ? ", ambient" : ", light")
                    << (device ? ", CPU" : ", GPU");
            }
            if (ambient) {
                EXPECT_NEAR(images[0][1].at(8, 8).x, 0.8 * occlusion, 1e-5);
            }
        }
    }
}

TEST_F(GpuMaterials, SpecularFactorZeroIsLambertian) {
    // KHR_materials_specular with factor 0: a glossy dielectric (roughness 0.3) under a directional light of
    // illuminance E shows exactly albedo / pi * E * cos(theta), which is what the conformance scenes need;
    // with factor 1 its highlight adds to that.
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(-0.3, 0.2, 1.0));
    const double albedo = 0.6, illuminance = 2.0;
    for (const float specular : {0.0f, 1.0f}) {
        Scene scene;
        Material material;
        material.baseColor = glm::vec4(glm::vec3(static_cast<float>(albedo)), 1.0f);
        material.metallic = 0.0f;
        material.roughness = 0.3f;
        material.specularFactor = specular;
        scene.lights.push_back(sunAlong(-toLight, illuminance));
        RenderSettings settings = ambientOnly(16);
        settings.ambient = glm::dvec3(0.0);
        settings.background = glm::dvec3(0.0);
        const auto [gpu, cpu] = renderSquare(scene, material, settings);
        const double lambert = albedo / M_PI * illuminance * toLight.z;
        for (const Image* image : {&gpu.image, &cpu.image}) {
            if (specular == 0.0f) {
                EXPECT_NEAR(image->at(8, 8).x, lambert, 1e-6);
            } else {
                EXPECT_GT(image->at(8, 8).x, lambert + 1e-3);
            }
        }
    }
}

// The rough lobes in closed form, written out here apart from the shaders: GGX's D, Heitz's height-correlated
// Smith G2 and the Fresnel terms (Schlick's for metals, the exact one for dielectrics) with alpha =
// roughness^2.
double ggxDistribution(double cosHalf, double alpha) {
    const double a2 = alpha * alpha, d = cosHalf * cosHalf * (a2 - 1.0) + 1.0;
    return a2 / (M_PI * d * d);
}

double smithLambda(double cosTheta, double alpha) {
    const double tan2 = (1.0 - cosTheta * cosTheta) / (cosTheta * cosTheta);
    return (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0) / 2.0;
}

double exactFresnel(double cosIn, double eta) {
    const double sin2Out = (1.0 - cosIn * cosIn) / (eta * eta), cosOut = std::sqrt(1.0 - sin2Out);
    const double s = (cosIn - eta * cosOut) / (cosIn + eta * cosOut);
    const double p = (eta * cosIn - cosOut) / (eta * cosIn + cosOut);
    return (s * s + p * p) / 2.0;
}

TEST_F(GpuMaterials, RoughLobesUnderASunMatchTheirClosedForm) {
    // Seen head-on (the orthographic camera: V = N), lit by a sun 35 degrees off the normal, without energy
    // compensation and with nothing else in view: a rough metal shows F_Schlick(F0, V.H) D G2 / (4 cos_o
    // cos_i) E cos_i, and a rough dielectric (ior 1.5) adds to its lobe (with the exact Fresnel term) the
    // Lambertian base's albedo (1 - F(N.V)) / pi E cos_i. Both integrators, both devices. (alpha = roughness
    // instead of its square fails every channel.)
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(std::sin(0.61), 0.0, std::cos(0.61)));
    const glm::dvec3 halfway = glm::normalize(toLight + glm::dvec3(0.0, 0.0, 1.0));
    const double illuminance = 3.0, roughness = 0.6, alpha = roughness * roughness, cosIn = toLight.z;
    const double cosHalf = halfway.z, viewHalf = halfway.z;  // V = N = +z
    const double lobe = ggxDistribution(cosHalf, alpha) /
                        (1.0 + smithLambda(1.0, alpha) + smithLambda(cosIn, alpha)) / (4.0 * 1.0 * cosIn) *
                        illuminance * cosIn;
    const glm::dvec3 metalColour(0.9, 0.6, 0.3);
    const double albedo = 0.5;
    for (const bool metal : {true, false}) {
        Material material;
        material.roughness = static_cast<float>(roughness);
        material.metallic = metal ? 1.0f : 0.0f;
        material.baseColor =
            metal ? glm::vec4(glm::vec3(metalColour), 1.0f) : glm::vec4(glm::vec3(albedo), 1.0f);
        glm::dvec3 expected;
        if (metal) {
            expected = (metalColour + (1.0 - metalColour) * std::pow(1.0 - viewHalf, 5.0)) * lobe;
        } else {
            expected = glm::dvec3(exactFresnel(viewHalf, 1.5) * lobe +
                                  albedo * (1.0 - exactFresnel(1.0, 1.5)) / M_PI * illuminance * cosIn);
        }
        for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
            SCOPED_TRACE(std::string(metal ? "metal" : "dielectric") +
                         (integrator == Integrator::Path ? ", paths" : ", Whitted"));
            Scene scene;
            scene.lights.push_back(sunAlong(-toLight, illuminance));
            RenderSettings settings = ambientOnly(8);
            settings.integrator = integrator;
            settings.ambient = glm::dvec3(0.0);
            settings.background = glm::dvec3(0.0);
            settings.energyCompensation = false;
            const auto [gpu, cpu] = renderSquare(scene, material, settings);
            for (const Image* image : {&gpu.image, &cpu.image}) {
                const glm::vec3 pixel = image->at(4, 4);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(pixel[c], expected[c], 1e-5 * expected[c]) << "channel " << c;
            }
        }
    }
}

TEST_F(GpuMaterials, NearMirrorMetalsReflectWhatAMirrorDoes) {
    // A metal sphere of roughness 0.0011 or 0.002 (alpha 1.2e-6 or 4e-6: a lobe a few 1e-6 rad wide) reflects
    // what a mirror does, here a small glowing sphere and the floor it lights, with both integrators. GGX's D
    // took the half vector's sin^2 as (1 - cos)(1 + cos), and a single-precision cosine within an ulp of 1
    // spans 3e-4 rad: D came out 0 or its peak, and the GPU's images were 2 to 9% dark (the highlight 27%),
    // the CPU's right.
    Scene base;
    base.materials.push_back(test::lambertian(0.7f));
    Material lamp = test::lambertian(0.0f);
    lamp.emission = glm::vec3(50.0f);
    base.materials.push_back(lamp);
    addFlatQuad(base, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, 0);
    base.spheres.push_back({{-2.0f, 3.0f, 1.0f}, 0.3f, 1});
    base.spheres.push_back({{0.0f, 1.0f, 0.0f}, 1.0f, 2});
    const Camera camera = lookAtCamera({0.0, 2.0, 5.0}, {0.0, 0.9, 0.0}, 0.785);
    auto render = [&](float roughness, Integrator integrator) {
        Scene scene = base;
        Material metal = test::lambertian(0.9f);
        metal.metallic = 1.0f;
        metal.roughness = roughness;
        scene.materials.push_back(metal);
        finalizeScene(scene);
        RenderSettings settings;
        settings.integrator = integrator;
        settings.ambient = glm::dvec3(0.0);
        settings.width = settings.height = 32;
        settings.samplesPerPixel = 64;
        return test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings,
                                     test::shaderCacheDir());
    };
    auto mean = [](const Image& image) {
        double sum = 0.0;
        for (const glm::vec3& p : image.pixels) sum += p.x + p.y + p.z;
        return sum / (3.0 * image.pixels.size());
    };
    for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        const double mirror = mean(render(0.0f, integrator).cpu.image);
        ASSERT_GT(mirror, 0.01);
        for (const float roughness : {0.0011f, 0.002f}) {
            const auto [gpu, cpu] = render(roughness, integrator);
            for (const RenderResult* result : {&gpu, &cpu}) {
                EXPECT_NEAR(mean(result->image), mirror, 1e-4 * mirror)
                    << (result == &gpu ? "GPU" : "CPU") << ", roughness " << roughness << ", "
                    << (integrator == Integrator::Path ? "paths" : "Whitted");
            }
            EXPECT_LT(compareImages(gpu.image, cpu.image).fractionOff, 0.002) << "roughness " << roughness;
        }
    }
}

TEST_F(GpuMaterials, MirrorsAndSmoothGlassCastNoShadowRays) {
    // Under a directional light, every camera ray meets the square, and a surface with a lobe that reflects
    // light (Lambert, rough metal) sends one shadow ray from its hit; a mirror and smooth (thin) glass
    // reflect the light only by their traced rays, and send none. The same on both devices, with both
    // integrators.
    Material mirror = lambertian(0.8f), roughMetal = lambertian(0.8f), glass = lambertian(0.8f);
    mirror.metallic = roughMetal.metallic = 1.0f;
    mirror.roughness = 0.0f;
    roughMetal.roughness = 0.5f;
    glass.transmission = 1.0f;
    glass.specularFactor = 1.0f;
    glass.roughness = 0.0f;
    for (const Integrator integrator : {Integrator::Whitted, Integrator::Path}) {
        for (const auto& [material, shadows] : {std::pair{lambertian(0.8f), true}, std::pair{mirror, false},
                                                std::pair{roughMetal, true}, std::pair{glass, false}}) {
            Scene scene;
            scene.lights.push_back(sunAlong(glm::vec3(0.2f, -0.3f, -1.0f), 2.0));
            RenderSettings settings = ambientOnly(8);
            settings.integrator = integrator;
            const auto [gpu, cpu] = renderSquare(scene, material, settings);
            for (const RenderResult* result : {&gpu, &cpu}) {
                EXPECT_EQ(result->rays.primary, 8u * 8u * 4u);
                EXPECT_EQ(result->rays.shadow, shadows ? result->rays.primary : 0u)
                    << "metallic " << material.metallic << ", roughness " << material.roughness
                    << ", transmission " << material.transmission << (result == &gpu ? ", GPU" : ", CPU");
            }
        }
    }
}

TEST_F(GpuMaterials, SpecularColorTintsTheReflectanceAtNormalIncidence) {
    // In ambient light, a matte dielectric (roughness 1: the lobe is not traced) shows its F0, which
    // KHR_materials_specular scales by the factor and tints by the colour (0.04 x 0.8 x colour for ior 1.5),
    // plus the albedo its specular layer leaves the base: 1 - max(F0) = 1 - 0.032 of it.
    Scene scene;
    Material material;
    material.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    material.metallic = 0.0f;
    material.roughness = 1.0f;
    material.specularFactor = 0.8f;
    material.specularColor = glm::vec3(0.5f, 1.0f, 0.25f);
    const auto [gpu, cpu] = renderSquare(scene, material, ambientOnly(16));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        const glm::vec3 pixel = image->at(8, 8);
        const double base = 0.5 * (1.0 - 0.04 * 0.8);
        EXPECT_NEAR(pixel.x, base + 0.04 * 0.8 * 0.5, 1e-6);
        EXPECT_NEAR(pixel.y, base + 0.04 * 0.8 * 1.0, 1e-6);
        EXPECT_NEAR(pixel.z, base + 0.04 * 0.8 * 0.25, 1e-6);
    }
}

TEST_F(GpuMaterials, SpecularColorTintsAtAnAngleAsTheExtensionsCurveDoes) {
    // A smooth black dielectric seen 60 degrees from its normal reflects the background (1; what a camera
    // ray's mirror images show) by its Fresnel term. KHR_materials_specular tints f0 = 0.04 by the colour and
    // leaves f90 white on Schlick's curve, so the tint adds f0 (colour - 1) (1 - 0.5^5) to the exact term of
    // the untinted channel, and a tint whose f0 would pass 1 stops at 1: a tint of 2 reflected 0.176 where
    // the extension's curve gives 0.128 with the exact term (0.109 with Schlick's), one of 0.25 0.024 where
    // it gives 0.060.
    Scene scene;
    Material material;
    material.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    material.metallic = 0.0f;
    material.roughness = 0.0f;
    material.specularColor = glm::vec3(2.0f, 1.0f, 0.25f);
    scene.materials.push_back(material);
    test::addUnitSquare(scene, 0);
    finalizeScene(scene);
    const double sin60 = std::sqrt(0.75);
    Camera camera = squareCamera();
    camera.forward = {0.0, -sin60, -0.5};
    camera.up = {0.0, 0.5, -sin60};
    camera.position = glm::dvec3(0.5, 0.5, 0.0) - 2.0 * camera.forward;
    camera.xmag = camera.ymag = 0.2;
    RenderSettings settings = ambientOnly(8);
    settings.background = glm::dvec3(1.0);
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvhFor(scene), camera, settings, test::shaderCacheDir());
    // The exact term at cosine 0.5 into index 1.5: cosT = sqrt(1 - 0.75 / 2.25).
    const double cosT = std::sqrt(1.0 - 0.75 / 2.25);
    const double rs = (0.5 - 1.5 * cosT) / (0.5 + 1.5 * cosT), rp = (0.75 - cosT) / (0.75 + cosT);
    const double exact = 0.5 * (rs * rs + rp * rp), shift = 0.04 * (1.0 - std::pow(0.5, 5.0));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        const glm::vec3 pixel = image->at(4, 4);
        EXPECT_NEAR(pixel.x, exact + shift, 1e-5);
        EXPECT_NEAR(pixel.y, exact, 1e-5);
        EXPECT_NEAR(pixel.z, exact - 0.75 * shift, 1e-5);
    }
}

TEST_F(GpuMaterials, SpecularColorDoesNotTintTransmittedLight) {
    // Thin-walled smooth glass head-on, KHR_materials_specular 0.5 in red: it reflects F = 0.5 x 0.04 x (1,
    // 0, 0) of the background (0.25) and passes 1 - max(F) = 0.98 of it in every channel (the spec's
    // fresnel_mix scales the base, transmission included, by 1 - max F); 1 - F per channel made the glass
    // cyan.
    Scene scene;
    Material material;
    material.baseColor = glm::vec4(1.0f);
    material.metallic = 0.0f;
    material.roughness = 0.0f;
    material.transmission = 1.0f;
    material.specularFactor = 0.5f;
    material.specularColor = glm::vec3(1.0f, 0.0f, 0.0f);
    const auto [gpu, cpu] = renderSquare(scene, material, ambientOnly(16));
    for (const Image* image : {&gpu.image, &cpu.image}) {
        const glm::vec3 pixel = image->at(8, 8);
        EXPECT_NEAR(pixel.x, 0.25 * (0.98 + 0.02), 1e-6);
        EXPECT_NEAR(pixel.y, 0.25 * 0.98, 1e-6);
        EXPECT_NEAR(pixel.z, 0.25 * 0.98, 1e-6);
    }
}

TEST_F(GpuMaterials, VertexColorsMultiplyTheBaseColour) {
    // COLOR_0 given at the corners as (x, y, 1 - x) interpolates exactly across the square (it is linear in
    // position): in ambient light a Lambertian square shows it pixel by pixel, times the base colour.
    Scene scene;
    Material material;
    material.baseColor = glm::vec4(0.5f, 1.0f, 1.0f, 1.0f);
    material.metallic = 0.0f;
    material.ior = 1.0f;
    scene.materials.push_back(material);
    addUnitSquare(scene, 0);
    for (const Triangle& t : scene.triangles) {
        std::array<glm::vec4, 3> colors;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 v = k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2;
            colors[k] = glm::vec4(v.x, v.y, 1.0f - v.x, 1.0f);
        }
        scene.vertexColors.push_back(colors);
    }
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    RenderSettings settings = ambientOnly(16);
    settings.samplesPerPixel = 64;
    const auto [gpu, cpu] =
        test::renderGpuAndCpu(context(), scene, bvh, squareCamera(), settings, test::shaderCacheDir());
    test::expectMatchesReference(gpu.image, cpu.image, "vertex-colors");
    for (const Image* image : {&gpu.image, &cpu.image}) {
        for (const glm::ivec2 p : {glm::ivec2(2, 3), glm::ivec2(8, 8), glm::ivec2(13, 11)}) {
            // A linear function averaged over a pixel is its value at the centre; 64 stratified samples
            // average to within 1/64 of a pixel (the colour changes by 1/16 per pixel), hence 2e-3.
            const double x = (p.x + 0.5) / 16.0, y = 1.0 - (p.y + 0.5) / 16.0;
            const glm::vec3 pixel = image->at(p.x, p.y);
            EXPECT_NEAR(pixel.x, 0.5 * x, 2e-3);
            EXPECT_NEAR(pixel.y, y, 2e-3);
            EXPECT_NEAR(pixel.z, 1.0 - x, 2e-3);
        }
    }
}

TEST_F(GpuMaterials, TextureCoordinateSetOneIsRead) {
    // The checker scaled by 4 (8 cells across) reads TEXCOORD_1, which spans the square; TEXCOORD_0 is zero
    // everywhere, so a binding that read it would see one white texel.
    for (const int texCoord : {1, 0}) {
        Scene scene;
        scene.textures.push_back(textureOf(2, 2, {0xffffffffu, 0xff000000u, 0xff000000u, 0xffffffffu}));
        Material checker;
        checker.metallic = 0.0f;
        checker.ior = 1.0f;
        checker.baseColorTexture.texture = 0;
        checker.baseColorTexture.texCoord = texCoord;
        checker.baseColorTexture.scale = glm::vec2(4.0f);
        scene.materials.push_back(checker);
        addUnitSquare(scene, 0);
        for (size_t i = 0; i < scene.triangles.size(); ++i) {
            std::array<glm::vec2, 3> set1;
            for (int k = 0; k < 3; ++k) {
                set1[k] = scene.shading[i].uv[k];
                scene.shading[i].uv[k] = glm::vec2(0.0f);
            }
            scene.uv1.push_back(set1);
        }
        finalizeScene(scene);
        // The second set's buffer and shader path exist only when a slot reads it.
        EXPECT_EQ(detectFeatures(scene).texCoords1, texCoord == 1);
        const FlatBvh bvh = bvhFor(scene);
        const auto [gpu, cpu] = test::renderGpuAndCpu(context(), scene, bvh, squareCamera(), ambientOnly(64),
                                                      test::shaderCacheDir());
        for (const Image* image : {&gpu.image, &cpu.image}) {
            EXPECT_EQ(cellsAlongRow(*image, 4), texCoord == 1 ? 8 : 1) << "TEXCOORD_" << texCoord;
        }
        test::expectMatchesReference(gpu.image, cpu.image, "texcoord1");
    }
}

}  // namespace
}  // namespace vkrt
