// Render policy: what the user asked for, plus the scene, gives the render settings and the camera. Every
// default that depends on the scene is decided here, once, for the command, the tools and the tests.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/render_settings.h"
#include "scene/scene.h"

namespace vkrt {

// What was asked; an unset optional leaves the choice to the scene.
struct RenderRequest {
    // Used as given, except that `height` and `ambient` below take precedence over settings.height and
    // settings.ambient.
    RenderSettings settings;
    // Unset: settings.width / the camera's aspect ratio when the file gives one, else settings.height.
    std::optional<int> height;
    // Unset: the path integrator (glTF describes physically based materials, and paths light them with all the
    // light there is).
    std::optional<Integrator> integrator;
    // Unset: kDefaultPathDepth for paths, kDefaultWhittedDepth for Whitted.
    std::optional<int> maxDepth;
    // Whitted's ambient term. Unset: 0 under an environment (it lights the scene instead); 0.05 in a lit scene;
    // 1, with a warning, in a scene without lights. Paths have no ambient term: there, an ambient radiance given
    // lights the scene as a uniform environment would (addNeutralEnvironment).
    std::optional<glm::dvec3> ambient;
    int camera = 0;                       // the file's camera in node order (0: the framing camera if none)
    std::optional<double> aperture;       // thin-lens radius; unset: the camera's
    std::optional<double> focusDistance;  // unset: the camera's, else the scene's centre along the view
};

// What to render with, and what the user should be told about the choices made.
struct RenderSetup {
    RenderSettings settings;
    Camera camera;
    std::vector<std::string> warnings;  // one line each, without a prefix
};

// Ambient radiance of a lit scene, and of a scene without lights (where it is the only light).
inline constexpr double kLitSceneAmbient = 0.05;
inline constexpr double kUnlitSceneAmbient = 1.0;
// Under an environment map, which lights every surface itself.
inline constexpr double kEnvironmentAmbient = 0.0;

// Bounces after the camera ray's hit unless asked otherwise: paths end by Russian roulette long before 64 in
// most scenes; Whitted's ray tree doubles with every level.
inline constexpr int kDefaultPathDepth = 64;
inline constexpr int kDefaultWhittedDepth = 8;

// The neutral environment: uniform radiance from every direction, as a 16 x 8 map.
inline constexpr double kNeutralEnvironmentRadiance = 1.0;

// A scene that has no lights of its own and was given neither an environment nor an ambient radiance is lit
// by the neutral environment (with shadows and reflections, where the Whitted ambient term has neither); for
// the path integrator, an ambient radiance given and no environment map make such a uniform environment of that
// radiance, lit or not. Adds it to `scene` and returns true; else leaves `scene` as it is. Call it before
// resolveRender. Camera rays do not see it: they see the background.
bool addNeutralEnvironment(const RenderRequest& request, Scene& scene);

// Punctual lights, emissive triangles, emissive spheres and emissive shapes light a scene.
bool sceneHasLights(const Scene& scene);

// The largest lens radius resolveRender takes, over the largest of the focus distance, the scene's size and
// its distance from the camera.
constexpr double kMaxApertureOverScene = 1e6;

// Whether the scene's only lights are triangles whose emission comes through an emissive texture (decals and
// screens of a model made for image-based lighting, rather than lamps).
bool onlyTexturedEmission(const Scene& scene);

// Which integrator the request asks for (unset: the path integrator).
Integrator integratorOf(const RenderRequest& request);

// Throws SceneError when request.camera does not exist, and when Whitted ray trees are asked to go deeper than
// the GPU's VKRT_MAX_RAY_DEPTH.
RenderSetup resolveRender(const RenderRequest& request, const Scene& scene);

}  // namespace vkrt
