// Loading real glTF files: every third-party scene loads (or names what it lacks), with counts checked.
#include <cmath>

#include <gtest/gtest.h>

#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

Scene loadReal(const std::string& relative) {
    return loadGltf((test::scenesReal() / relative).string());
}

#define REQUIRE_SCENES_REAL() \
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal()

TEST(GltfLoader, EveryThirdPartySceneLoads) {
    REQUIRE_SCENES_REAL();
    const auto files = test::gltfFilesUnder(test::scenesReal());
    ASSERT_GE(files.size(), 15u);
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        try {
            const Scene scene = loadGltf(file.string());
            EXPECT_FALSE(scene.triangles.empty());
            EXPECT_EQ(scene.triangles.size(), scene.shading.size());
            EXPECT_FALSE(scene.bounds.empty());
            for (const Triangle& t : scene.triangles) ASSERT_LT(t.material, scene.materials.size());
        } catch (const SceneError& e) {
            // Allowed only when the file needs something vkrt names as unsupported.
            EXPECT_NE(std::string(e.what()).find("does not support"), std::string::npos) << e.what();
        }
    }
}

TEST(GltfLoader, VkrtSphereIsPlacedByItsNodeTransform) {
    // A sphere of radius 0.5 under a parent that scales by 2 and translates, declared required.
    const std::filesystem::path file = test::temporaryFolder() / "spheres.gltf";
    test::writeText(file, R"({
        "asset": {"version": "2.0"}, "extensionsUsed": ["VKRT_sphere"], "extensionsRequired": ["VKRT_sphere"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "materials": [{"name": "a"}, {"name": "lamp", "emissiveFactor": [1, 1, 1]}],
        "nodes": [
            {"translation": [10, 0, 0], "scale": [2, 2, 2], "children": [1, 2]},
            {"translation": [0, 1, 0], "extensions": {"VKRT_sphere": {"radius": 0.5, "material": 1}}},
            {"extensions": {"VKRT_sphere": {"radius": 0.25}}}
        ]})");
    const Scene scene = loadGltf(file.string());
    ASSERT_EQ(scene.spheres.size(), 2u);
    EXPECT_TRUE(scene.triangles.empty());
    const glm::dvec3 first = glm::dvec3(scene.spheres[0].center) + scene.origin;
    EXPECT_NEAR(first.x, 10.0, 1e-5);
    EXPECT_NEAR(first.y, 2.0, 1e-5);
    EXPECT_NEAR(first.z, 0.0, 1e-5);
    EXPECT_FLOAT_EQ(scene.spheres[0].radius, 1.0f);
    EXPECT_EQ(scene.spheres[0].material, 1u);
    EXPECT_FLOAT_EQ(scene.spheres[1].radius, 0.5f);
    EXPECT_EQ(scene.materials[scene.spheres[1].material].name, "default");
    EXPECT_EQ(scene.emissiveSpheres, std::vector<uint32_t>{0});
    EXPECT_EQ(scene.primitiveCount(), 2u);
    EXPECT_TRUE(scene.isSphere(0));
    // The bounds hold both spheres.
    EXPECT_NEAR(scene.bounds.max.y + scene.origin.y, 3.0, 1e-4);
    EXPECT_NEAR(scene.bounds.min.y + scene.origin.y, -0.5, 1e-4);
}

TEST(GltfLoader, NodeAnimationsPlacePrimitivesAtTheShutterEnds) {
    // scenes/motion-blur.gltf: shutter [0, 0.5] from the scene's extras; a cube sliding +1.5 units/s in x
    // (LINEAR), a cube turning 90 degrees/s about y (LINEAR), a ball jumping up 0.8 at t = 0.25 (STEP).
    const Scene scene = loadGltf((test::sourceDir() / "scenes/motion-blur.gltf").string());
    EXPECT_EQ(scene.shutterOpen, 0.0);
    EXPECT_EQ(scene.shutterClose, 0.5);
    ASSERT_TRUE(scene.moving());
    // Rotation and a step inside the shutter: the full set of segments.
    const int segments = scene.motionSegments;
    ASSERT_EQ(segments, kMotionSegments);
    ASSERT_EQ(scene.trianglePoses.size(), scene.triangles.size() * segments);
    ASSERT_EQ(scene.spherePoses.size(), static_cast<size_t>(segments));
    size_t sliding = 0, turning = 0, still = 0;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::vec3 a = scene.triangles[i].v0,
                        b = scene.trianglePose(static_cast<uint32_t>(i), segments).v0;
        const glm::vec3 shift = b - a;
        if (glm::length(shift) == 0.0f) {
            ++still;
        } else if (std::abs(shift.x - 0.75f) < 1e-5f && std::abs(shift.y) < 1e-5f &&
                   std::abs(shift.z) < 1e-5f) {
            ++sliding;
        } else {
            // Turning about the cube's vertical axis through (1.6, *, 1.0) (scene coordinates are
            // re-centred): the height and the distance from the axis stay, the angle grows by 45 degrees.
            const glm::dvec3 axis = glm::dvec3(1.6, 0.0, 1.0) - scene.origin;
            const glm::dvec2 p(a.x - axis.x, a.z - axis.z), q(b.x - axis.x, b.z - axis.z);
            EXPECT_NEAR(a.y, b.y, 1e-5);
            EXPECT_NEAR(glm::length(p), glm::length(q), 1e-5);
            const double turned = std::atan2(p.x * q.y - p.y * q.x, glm::dot(p, q));
            EXPECT_NEAR(std::abs(turned), M_PI / 4.0, 1e-5);
            ++turning;
        }
    }
    EXPECT_EQ(sliding, 12u);
    EXPECT_EQ(turning, 12u);
    EXPECT_EQ(still, scene.triangles.size() - 24u);
    // STEP: the ball stays until t = 0.25 (pose 8 of 16 over [0, 0.5]), then is 0.8 higher.
    const uint32_t ball = static_cast<uint32_t>(scene.triangles.size());
    EXPECT_EQ(scene.spherePose(ball, 7).center.y, scene.spheres[0].center.y);
    EXPECT_NEAR(scene.spherePose(ball, 8).center.y - scene.spheres[0].center.y, 0.8f, 1e-5f);
    EXPECT_NEAR(scene.spherePose(ball, segments).center.y - scene.spheres[0].center.y, 0.8f, 1e-5f);
    // Shutter closed: nothing moves.
    LoadOptions closed;
    closed.shutter = std::array<double, 2>{0.25, 0.25};
    const Scene frozen = loadGltf((test::sourceDir() / "scenes/motion-blur.gltf").string(), closed);
    EXPECT_FALSE(frozen.moving());
    EXPECT_NEAR(frozen.spheres[0].center.y + frozen.origin.y, 1.3, 1e-5);  // STEP: the second key from 0.25
}

TEST(GltfLoader, BoxCounts) {
    REQUIRE_SCENES_REAL();
    for (const char* file : {"khronos-Box/glTF/Box.gltf", "khronos-Box/glTF-Binary/Box.glb"}) {
        const Scene scene = loadReal(file);
        EXPECT_EQ(scene.triangles.size(), 12u) << file;
        EXPECT_TRUE(scene.cameras.empty()) << file;
        // The Box's node rotates it by -90 degrees about x: its 1 x 1 x 1 extent stays a unit cube.
        EXPECT_NEAR(scene.bounds.extent().x, 1.0f, 1e-5f);
        EXPECT_NEAR(scene.bounds.extent().y, 1.0f, 1e-5f);
        EXPECT_NEAR(scene.bounds.extent().z, 1.0f, 1e-5f);
    }
}

TEST(GltfLoader, DuckHasTexturedMaterialAndCamera) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-Duck/glTF/Duck.gltf");
    EXPECT_EQ(scene.triangles.size(), 4212u);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_EQ(scene.cameras[0].projection, Projection::Perspective);
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_GT(scene.textures[0].width, 0);
    EXPECT_EQ(scene.materials[scene.triangles[0].material].baseColorTexture, 0);
    // The binary and text versions are the same model.
    EXPECT_EQ(loadReal("khronos-Duck/glTF-Binary/Duck.glb").triangles.size(), 4212u);
}

TEST(GltfLoader, CamerasPerspectiveAndOrthographic) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-Cameras/glTF/Cameras.gltf");
    ASSERT_EQ(scene.cameras.size(), 2u);
    EXPECT_EQ(scene.cameras[0].projection, Projection::Perspective);
    EXPECT_EQ(scene.cameras[1].projection, Projection::Orthographic);
    EXPECT_EQ(selectCamera(scene, 1, 1.0).projection, Projection::Orthographic);
    EXPECT_THROW(selectCamera(scene, 2, 1.0), SceneError);
}

TEST(GltfLoader, PunctualLightsInPhotometricUnits) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("playcanvas-lights/Lights.glb");
    int point = 0, spot = 0, directional = 0;
    for (const PunctualLight& light : scene.lights) {
        point += light.type == LightType::Point;
        spot += light.type == LightType::Spot;
        directional += light.type == LightType::Directional;
        EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-9);
        if (light.type == LightType::Spot) {
            EXPECT_LT(light.innerConeAngle, light.outerConeAngle);
        }
    }
    EXPECT_EQ(point, 1);
    EXPECT_EQ(spot, 2);
    EXPECT_EQ(directional, 1);
}

TEST(GltfLoader, GpuInstancingExpandsInstances) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-SimpleInstancing/SimpleInstancing.glb");
    EXPECT_EQ(scene.triangles.size(), 12u * 125u);
}

TEST(GltfLoader, VolumeAndTransmissionExtensions) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("khronos-AttenuationTest/AttenuationTest.glb");
    int volumes = 0, attenuating = 0;
    for (const Material& m : scene.materials) {
        volumes += m.hasVolume() && m.transmission > 0.0f;
        attenuating += std::isfinite(m.attenuationDistance);
    }
    EXPECT_GT(volumes, 0);
    EXPECT_GT(attenuating, 0);
}

TEST(GltfLoader, NvidiaCornellWarnsAboutItsVendorExtension) {
    REQUIRE_SCENES_REAL();
    const Scene scene = loadReal("cornell-box-nvidia/cornellBox.gltf");
    bool named = false;
    for (const std::string& warning : scene.warnings)
        named |= warning.find("NV_materials_mdl") != std::string::npos;
    EXPECT_TRUE(named);
    EXPECT_FALSE(scene.emissiveTriangles.empty());
}

TEST(GltfLoader, OwnCornellBoxMatchesThePublishedData) {
    const Scene scene = loadGltf((test::sourceDir() / "scenes/cornell.gltf").string());
    EXPECT_EQ(scene.triangles.size(), 38u);  // 5 walls (ceiling in 4 parts), 2 blocks of 5 faces, the light
    EXPECT_EQ(scene.emissiveTriangles.size(), 2u);
    ASSERT_EQ(scene.cameras.size(), 1u);
    const Camera& camera = scene.cameras[0];
    EXPECT_NEAR(camera.yfov, 2.0 * std::atan(12.5 / 35.0), 1e-12);
    // Stored positions are relative to scene.origin (the middle of the box).
    const glm::dvec3 eye = camera.position + scene.origin;
    EXPECT_NEAR(eye.x, 0.278, 1e-9);
    EXPECT_NEAR(eye.y, 0.273, 1e-9);
    EXPECT_NEAR(eye.z, -0.800, 1e-9);
    EXPECT_NEAR(camera.forward.z, 1.0, 1e-12);
    EXPECT_NEAR(camera.up.y, 1.0, 1e-12);
    // Box extents in metres: 556.0 x 548.8 x 559.2 mm, from (0, 0, 0).
    const glm::dvec3 lo = glm::dvec3(scene.bounds.min) + scene.origin,
                     hi = glm::dvec3(scene.bounds.max) + scene.origin;
    EXPECT_NEAR(lo.x, 0.0, 1e-6);
    EXPECT_NEAR(lo.y, 0.0, 1e-6);
    EXPECT_NEAR(lo.z, 0.0, 1e-6);
    EXPECT_NEAR(hi.x, 0.556, 1e-6);
    EXPECT_NEAR(hi.y, 0.5488, 1e-6);
    EXPECT_NEAR(hi.z, 0.5592, 1e-6);
    EXPECT_NEAR(scene.origin.x, 0.278, 1e-9);
    // The light faces down into the box.
    for (uint32_t index : scene.emissiveTriangles) {
        const Triangle& t = scene.triangles[index];
        EXPECT_LT(glm::cross(t.v1 - t.v0, t.v2 - t.v0).y, 0.0f);
    }
}

TEST(GltfLoader, OwnScenesLoad) {
    const Scene whitted = loadGltf((test::sourceDir() / "scenes/whitted.gltf").string());
    EXPECT_EQ(whitted.lights.size(), 1u);
    int mirrors = 0, glass = 0;
    for (const Material& m : whitted.materials) {
        mirrors += m.metallic == 1.0f && m.roughness == 0.0f;
        glass += m.transmission == 1.0f && m.hasVolume();
    }
    EXPECT_EQ(mirrors, 1);
    EXPECT_EQ(glass, 1);
    const Scene lights = loadGltf((test::sourceDir() / "scenes/lights.gltf").string());
    ASSERT_EQ(lights.lights.size(), 3u);
    EXPECT_EQ(lights.lights[0].type, LightType::Point);
    EXPECT_EQ(lights.lights[1].type, LightType::Spot);
    EXPECT_EQ(lights.lights[2].type, LightType::Directional);
    EXPECT_NEAR(lights.lights[1].direction.y, -1.0, 1e-9);  // the spot points down
}

TEST(CameraSelection, DefaultCameraFramesTheScene) {
    Aabb bounds;
    bounds.grow(glm::vec3(-1.0f, -2.0f, -3.0f));
    bounds.grow(glm::vec3(3.0f, 2.0f, 1.0f));
    for (double aspect : {0.5, 1.0, 2.0}) {
        const Camera camera = frameBounds(bounds, aspect);
        EXPECT_TRUE(camera.generated);
        // The bounding sphere's silhouette fits both fields of view.
        const glm::dvec3 center(1.0, 0.0, -1.0);
        const double radius = glm::length(glm::dvec3(2.0, 2.0, 2.0));
        const double distance = glm::length(center - camera.position);
        const double halfAngle = std::asin(radius / distance);
        const double halfY = 0.5 * camera.yfov;
        const double halfX = std::atan(std::tan(halfY) * aspect);
        EXPECT_LE(halfAngle, std::min(halfX, halfY) + 1e-9) << aspect;
    }
}

}  // namespace
}  // namespace vkrt
