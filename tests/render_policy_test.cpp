// The render policy: the integrator and its depth, which scenes count as lit, Whitted's ambient default, the
// image height, the camera and its focus.
#include <algorithm>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "app/render_policy.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

// A grey unit square around the origin in the z = 0 plane, with no lights.
Scene darkSquare() {
    Scene scene;
    Material grey;
    grey.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    scene.materials.push_back(grey);
    addFlatQuad(scene, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, 0);
    finalizeScene(scene);
    return scene;
}

uint32_t addEmissiveMaterial(Scene& scene) {
    Material glow;
    glow.emission = glm::vec3(2.0f);
    scene.materials.push_back(glow);
    return static_cast<uint32_t>(scene.materials.size() - 1);
}

// A camera 5 units in front of the square, looking at it.
// A request for Whitted's integrator, whose ambient term the policy chooses.
RenderRequest whitted() {
    RenderRequest request;
    request.integrator = Integrator::Whitted;
    return request;
}

Camera cameraInFront(double aspectRatio) {
    Camera camera;
    camera.name = "front";
    camera.position = glm::dvec3(0.0, 0.0, 5.0);
    camera.aspectRatio = aspectRatio;
    return camera;
}

TEST(RenderPolicy, SceneWithoutLightsGetsAmbientOneAndAWarning) {
    const Scene scene = darkSquare();
    EXPECT_FALSE(sceneHasLights(scene));
    const RenderSetup setup = resolveRender(whitted(), scene);
    EXPECT_EQ(setup.settings.ambient, glm::dvec3(kUnlitSceneAmbient));
    ASSERT_EQ(setup.warnings.size(), 1u);
    EXPECT_NE(setup.warnings[0].find("no lights"), std::string::npos) << setup.warnings[0];
}

TEST(RenderPolicy, SceneWithoutLightsGetsTheNeutralEnvironment) {
    // What the command does: a scene without lights, environment or ambient gets a uniform map of radiance 1
    // and no ambient term, with a warning; lights, a map or an asked ambient keep it out.
    Scene scene = darkSquare();
    ASSERT_TRUE(addNeutralEnvironment(RenderRequest{}, scene));
    ASSERT_TRUE(scene.environment.present());
    EXPECT_TRUE(scene.environment.neutral);
    for (const glm::vec3& texel : scene.environment.radiance) EXPECT_EQ(texel, glm::vec3(kNeutralEnvironmentRadiance));
    const RenderSetup setup = resolveRender(RenderRequest{}, scene);
    EXPECT_EQ(setup.settings.ambient, glm::dvec3(kEnvironmentAmbient));
    ASSERT_EQ(setup.warnings.size(), 1u);
    EXPECT_NE(setup.warnings[0].find("neutral environment"), std::string::npos) << setup.warnings[0];
    EXPECT_FALSE(addNeutralEnvironment(RenderRequest{}, scene));  // it has one now
    RenderRequest ambient = whitted();
    ambient.ambient = glm::dvec3(0.5);
    Scene asked = darkSquare();
    EXPECT_FALSE(addNeutralEnvironment(ambient, asked));
    Scene lit = darkSquare();
    lit.lights.push_back(PunctualLight{});
    EXPECT_FALSE(addNeutralEnvironment(RenderRequest{}, lit));
}

TEST(RenderPolicy, PathsAreTheDefaultWithoutAnAmbientTerm) {
    // Paths by default, 64 bounces deep, and no ambient term (it is Whitted's); Whitted goes 8 deep, at most
    // VKRT_MAX_RAY_DEPTH; either depth can be asked.
    Scene scene = darkSquare();
    scene.lights.push_back(PunctualLight{});
    const RenderSetup paths = resolveRender(RenderRequest{}, scene);
    EXPECT_EQ(paths.settings.integrator, Integrator::Path);
    EXPECT_EQ(paths.settings.maxDepth, kDefaultPathDepth);
    EXPECT_EQ(paths.settings.ambient, glm::dvec3(0.0));
    EXPECT_TRUE(paths.warnings.empty());
    const RenderSetup classic = resolveRender(whitted(), scene);
    EXPECT_EQ(classic.settings.integrator, Integrator::Whitted);
    EXPECT_EQ(classic.settings.maxDepth, kDefaultWhittedDepth);
    RenderRequest deep;
    deep.maxDepth = kMaxPathDepth;
    EXPECT_EQ(resolveRender(deep, scene).settings.maxDepth, kMaxPathDepth);
    deep.integrator = Integrator::Whitted;
    EXPECT_THROW(resolveRender(deep, scene), SceneError);
    deep.maxDepth = 24;
    EXPECT_EQ(resolveRender(deep, scene).settings.maxDepth, 24);
}

TEST(RenderPolicy, PathsTakeAnAskedAmbientAsAUniformEnvironment) {
    // For paths, --ambient R,G,B lights the scene as a uniform environment of that radiance would (camera rays
    // still see the background), lit or not; a map given wins.
    for (const bool lit : {false, true}) {
        Scene scene = darkSquare();
        if (lit) scene.lights.push_back(PunctualLight{});
        RenderRequest request;
        request.ambient = glm::dvec3(0.0, 0.25, 0.5);
        ASSERT_TRUE(addNeutralEnvironment(request, scene));
        EXPECT_TRUE(scene.environment.neutral);
        for (const glm::vec3& texel : scene.environment.radiance) EXPECT_EQ(texel, glm::vec3(0.0f, 0.25f, 0.5f));
        const RenderSetup setup = resolveRender(request, scene);
        EXPECT_EQ(setup.settings.ambient, glm::dvec3(0.0));
        EXPECT_TRUE(setup.warnings.empty());
    }
    Scene mapped = darkSquare();
    mapped.environment = makeEnvironmentMap("sky.hdr", 2, 1, {glm::vec3(1.0f), glm::vec3(2.0f)}, 0.0, 1.0);
    RenderRequest request;
    request.ambient = glm::dvec3(0.5);
    EXPECT_FALSE(addNeutralEnvironment(request, mapped));
    const RenderSetup setup = resolveRender(request, mapped);
    ASSERT_EQ(setup.warnings.size(), 1u);
    EXPECT_NE(setup.warnings[0].find("--ambient is Whitted's"), std::string::npos) << setup.warnings[0];
}

TEST(RenderPolicy, AskedAmbientWinsWithoutAWarning) {
    RenderRequest request = whitted();
    request.ambient = glm::dvec3(0.0, 0.25, 0.5);
    const RenderSetup setup = resolveRender(request, darkSquare());
    EXPECT_EQ(setup.settings.ambient, glm::dvec3(0.0, 0.25, 0.5));
    EXPECT_TRUE(setup.warnings.empty());
}

TEST(RenderPolicy, EnvironmentLightsTheSceneWithoutAmbient) {
    Scene scene = darkSquare();
    scene.environment = makeEnvironmentMap("sky.hdr", 2, 1, {glm::vec3(1.0f), glm::vec3(2.0f)}, 0.0, 1.0);
    const RenderSetup setup = resolveRender(RenderRequest{}, scene);
    EXPECT_EQ(setup.settings.ambient, glm::dvec3(kEnvironmentAmbient));
    EXPECT_TRUE(setup.warnings.empty());
    RenderRequest request = whitted();
    request.ambient = glm::dvec3(0.1);
    EXPECT_EQ(resolveRender(request, scene).settings.ambient, glm::dvec3(0.1));
}

void expectLit(const Scene& scene, const char* by) {
    EXPECT_TRUE(sceneHasLights(scene)) << by;
    const RenderSetup setup = resolveRender(whitted(), scene);
    EXPECT_EQ(setup.settings.ambient, glm::dvec3(kLitSceneAmbient)) << by;
    EXPECT_TRUE(setup.warnings.empty()) << by;
}

TEST(RenderPolicy, UnlitEmissiveMaterialLightsNothing) {
    // KHR_materials_unlit shows the base colour and ignores emission: such a surface is no light, else light
    // samples would find light that rays hitting it never see.
    Scene scene = darkSquare();
    scene.materials[0].emission = glm::vec3(5.0f);
    scene.materials[0].unlit = true;
    finalizeScene(scene);
    EXPECT_TRUE(scene.emissiveTriangles.empty());
    EXPECT_FALSE(sceneHasLights(scene));
}

TEST(RenderPolicy, PunctualLightLightsTheScene) {
    Scene scene = darkSquare();
    PunctualLight light;
    light.type = LightType::Point;
    scene.lights.push_back(light);
    expectLit(scene, "a point light");
}

TEST(RenderPolicy, EmissiveTriangleLightsTheScene) {
    Scene scene = darkSquare();
    const uint32_t glow = addEmissiveMaterial(scene);
    addFlatTriangle(scene, {-1, 2, 0}, {1, 2, 0}, {0, 3, 0}, glow);
    finalizeScene(scene);
    ASSERT_EQ(scene.emissiveTriangles.size(), 1u);
    expectLit(scene, "an emissive triangle");
}

// A model whose only emitters are textured (DamagedHelmet's decals, made for image-based lighting) is lit by
// them as it asks, and the command says how to light it otherwise; an untextured emitter is a lamp, said
// nothing of.
TEST(RenderPolicy, LightFromEmissiveTexturesAloneIsSaid) {
    Scene scene = darkSquare();
    const uint32_t glow = addEmissiveMaterial(scene);
    addFlatTriangle(scene, {-1, 2, 0}, {1, 2, 0}, {0, 3, 0}, glow);
    Texture white;
    white.width = white.height = 1;
    white.rgba = std::make_shared<const std::vector<uint8_t>>(std::vector<uint8_t>{255, 255, 255, 255});
    scene.textures.push_back(white);
    scene.materials[glow].emissiveTexture.texture = 0;
    finalizeScene(scene);
    ASSERT_TRUE(sceneHasLights(scene));
    EXPECT_TRUE(onlyTexturedEmission(scene));
    const RenderSetup setup = resolveRender(RenderRequest{}, scene);
    ASSERT_EQ(setup.warnings.size(), 1u);
    EXPECT_NE(setup.warnings[0].find("only lights are surfaces with emissive textures"), std::string::npos)
        << setup.warnings[0];
    RenderRequest ambient;
    ambient.ambient = glm::dvec3(0.5);
    EXPECT_TRUE(resolveRender(ambient, scene).warnings.empty());
    // With a lamp beside them, nothing is said.
    const uint32_t lamp = addEmissiveMaterial(scene);
    addFlatTriangle(scene, {-1, 4, 0}, {1, 4, 0}, {0, 5, 0}, lamp);
    finalizeScene(scene);
    EXPECT_FALSE(onlyTexturedEmission(scene));
    EXPECT_TRUE(resolveRender(RenderRequest{}, scene).warnings.empty());
}

// A lens radius a million times the scene and its distance is refused: in single precision the GPU's rays
// from a lens of radius 1e10 missed the scene the CPU's met, and gave a brighter image without a word.
TEST(RenderPolicy, ALensTooLargeToAimIsRefused) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(1.0));
    RenderRequest request;
    request.aperture = 1e5;  // 5 units away: within a million times
    EXPECT_NO_THROW(resolveRender(request, scene));
    request.aperture = 1e10;
    try {
        resolveRender(request, scene);
        ADD_FAILURE() << "a lens of radius 1e10 was taken";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot be aimed in single precision"), std::string::npos)
            << e.what();
    }
}

TEST(RenderPolicy, EmissiveSphereLightsTheScene) {
    Scene scene = darkSquare();
    const uint32_t glow = addEmissiveMaterial(scene);
    scene.spheres.push_back(Sphere{{0.0f, 2.0f, 0.0f}, 0.5f, glow});
    scene.emissiveSpheres.push_back(0);
    expectLit(scene, "an emissive sphere");
}

TEST(RenderPolicy, HeightFollowsTheCameraAspectRatioWhenNotAsked) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(2.0));
    RenderRequest request;
    request.settings.width = 101;
    const RenderSetup setup = resolveRender(request, scene);
    EXPECT_EQ(setup.settings.width, 101);
    EXPECT_EQ(setup.settings.height, 51);  // 50.5 rounds up
    EXPECT_EQ(setup.camera.name, "front");
}

// A height from a narrow aspect ratio beyond the largest image side is refused (it overflowed an int, and
// came out as any height from 1 up), saying the ratio (shown as 0.000000 where it was below 1e-6); a wide
// one's height is at least 1.
TEST(RenderPolicy, HeightFromTheAspectRatioStaysWithinTheLargestSide) {
    for (const auto& [aspect, shown] : {std::pair{0.001, "0.001"}, {1.49e-8, "1.49e-08"}, {1e-30, "1e-30"}}) {
        Scene scene = darkSquare();
        scene.cameras.push_back(cameraInFront(aspect));
        RenderRequest request;
        request.settings.width = 64;
        try {
            resolveRender(request, scene);
            ADD_FAILURE() << aspect << " was not refused";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("aspect ratio ") + shown + " makes"),
                      std::string::npos)
                << e.what();
        }
    }
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(1e30));
    RenderRequest request;
    request.settings.width = 64;
    EXPECT_EQ(resolveRender(request, scene).settings.height, 1);
}

TEST(RenderPolicy, HeightFollowsAnOrthographicCamerasMagnificationsWhenNotAsked) {
    // xmag 2 and ymag 1 see a 4 x 2 view: a 64-pixel-wide image of it is 32 high, not stretched to 64.
    Scene scene = darkSquare();
    Camera camera = cameraInFront(0.0);
    camera.projection = Projection::Orthographic;
    camera.xmag = 2.0;
    camera.ymag = 1.0;
    scene.cameras.push_back(camera);
    RenderRequest request;
    request.settings.width = 64;
    request.settings.height = 64;
    EXPECT_EQ(resolveRender(request, scene).settings.height, 32);
    request.height = 48;
    EXPECT_EQ(resolveRender(request, scene).settings.height, 48);
    // It has no lens: an aperture is ignored, and vkrt says so.
    request.aperture = 0.1;
    const RenderSetup setup = resolveRender(request, scene);
    EXPECT_EQ(setup.camera.aperture, 0.0);
    EXPECT_TRUE(std::any_of(setup.warnings.begin(), setup.warnings.end(), [](const std::string& w) {
        return w.find("an orthographic camera has no lens") != std::string::npos;
    }));
}

TEST(RenderPolicy, AskedHeightWinsOverTheAspectRatio) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(2.0));
    RenderRequest request;
    request.settings.width = 100;
    request.height = 80;
    EXPECT_EQ(resolveRender(request, scene).settings.height, 80);
}

TEST(RenderPolicy, WithoutAnAspectRatioTheHeightIsTheSettings) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(0.0));
    RenderRequest request;
    request.settings.width = 100;
    request.settings.height = 70;
    EXPECT_EQ(resolveRender(request, scene).settings.height, 70);
    // Without cameras the framing camera uses the image's aspect ratio.
    EXPECT_TRUE(resolveRender(request, darkSquare()).camera.generated);
}

TEST(RenderPolicy, MissingCameraIsASceneError) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(1.0));
    RenderRequest request;
    request.camera = 1;
    EXPECT_THROW(resolveRender(request, scene), SceneError);
}

TEST(RenderPolicy, ApertureWithoutFocusFocusesOnTheSceneCentre) {
    Scene scene = darkSquare();
    scene.cameras.push_back(cameraInFront(1.0));
    RenderRequest request;
    EXPECT_EQ(resolveRender(request, scene).camera.aperture, 0.0);
    request.aperture = 0.1;
    const Camera camera = resolveRender(request, scene).camera;
    EXPECT_EQ(camera.aperture, 0.1);
    EXPECT_NEAR(camera.focusDistance, 5.0, 1e-9);  // the square's centre, 5 units along the view
}

TEST(RenderPolicy, AskedFocusDistanceAndTheCamerasOwnWin) {
    Scene scene = darkSquare();
    Camera lens = cameraInFront(1.0);
    lens.aperture = 0.2;
    lens.focusDistance = 3.0;
    scene.cameras.push_back(lens);
    RenderRequest request;
    EXPECT_EQ(resolveRender(request, scene).camera.focusDistance, 3.0);
    request.focusDistance = 7.0;
    EXPECT_EQ(resolveRender(request, scene).camera.focusDistance, 7.0);
    EXPECT_EQ(resolveRender(request, scene).camera.aperture, 0.2);
}

}  // namespace
}  // namespace vkrt
