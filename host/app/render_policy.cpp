#include "app/render_policy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene/camera_selection.h"
#include "scene/scene_error.h"
#include "shared.h"

namespace vkrt {

bool sceneHasLights(const Scene& scene) {
    return !scene.lights.empty() || !scene.emissiveTriangles.empty() || !scene.emissiveSpheres.empty() ||
           !scene.emissiveShapes.empty();
}

Integrator integratorOf(const RenderRequest& request) {
    return request.integrator.value_or(Integrator::Path);
}

bool addNeutralEnvironment(const RenderRequest& request, Scene& scene) {
    if (scene.environment.present()) return false;
    glm::dvec3 radiance(kNeutralEnvironmentRadiance);
    if (request.ambient) {
        if (integratorOf(request) != Integrator::Path) return false;  // Whitted's ambient term lights it
        radiance = *request.ambient;
    } else if (sceneHasLights(scene)) {
        return false;
    }
    constexpr int kWidth = 16, kHeight = 8;
    scene.environment = makeEnvironmentMap("neutral", kWidth, kHeight,
                                           std::vector<glm::vec3>(kWidth * kHeight, glm::vec3(radiance)), 0.0, 1.0);
    scene.environment.neutral = true;
    return true;
}

RenderSetup resolveRender(const RenderRequest& request, const Scene& scene) {
    RenderSetup setup;
    RenderSettings& settings = setup.settings;
    settings = request.settings;
    settings.integrator = integratorOf(request);
    const bool paths = settings.integrator == Integrator::Path;
    settings.maxDepth = request.maxDepth.value_or(paths ? kDefaultPathDepth : kDefaultWhittedDepth);
    if (!paths && settings.maxDepth > VKRT_MAX_RAY_DEPTH) {
        throw SceneError("--max-depth " + std::to_string(settings.maxDepth) + ": Whitted ray trees go at most " +
                         std::to_string(VKRT_MAX_RAY_DEPTH) + " deep (paths up to " + std::to_string(kMaxPathDepth) +
                         ")");
    }

    // Image size: a file camera with an aspect ratio (a perspective camera's aspectRatio, an orthographic
    // one's xmag / ymag) sets the height unless it was asked for, so the image is not stretched.
    if (request.height) {
        settings.height = *request.height;
    } else if (request.camera >= 0 && request.camera < static_cast<int>(scene.cameras.size())) {
        const Camera& file = scene.cameras[request.camera];
        const double aspect =
            file.projection == Projection::Orthographic ? std::abs(file.xmag / file.ymag) : file.aspectRatio;
        if (aspect > 0.0 && std::isfinite(aspect)) {
            const double height = std::max(1.0, std::round(settings.width / aspect));
            if (!(height <= kMaxImageSide)) {
                char shown[32];  // %g: std::to_string showed 1e-9 as 0.000000
                std::snprintf(shown, sizeof shown, "%.3g", aspect);
                throw SceneError("camera " + std::to_string(request.camera) + "'s aspect ratio " + shown +
                                 " makes the image " + std::to_string(settings.width) +
                                 " wide and more than " + std::to_string(kMaxImageSide) +
                                 " pixels high; give --height");
            }
            settings.height = static_cast<int>(height);
        }
    }

    // Camera, with the lens overrides; a lens without a focus distance focuses on the middle of the scene,
    // measured along the view direction.
    Camera& camera = setup.camera;
    camera = selectCamera(scene, request.camera, static_cast<double>(settings.width) / settings.height);
    if (request.aperture) camera.aperture = *request.aperture;
    if (request.focusDistance) camera.focusDistance = *request.focusDistance;
    const bool orthographic = camera.projection == Projection::Orthographic;
    if (orthographic && (camera.aperture > 0.0 || request.focusDistance)) {
        setup.warnings.push_back(
            "an orthographic camera has no lens: its aperture and focus distance are ignored");
        camera.aperture = 0.0;
    } else if (request.focusDistance && !(camera.aperture > 0.0)) {
        setup.warnings.push_back(
            "--focus-distance focuses a lens, and the camera is a pinhole (--aperture R makes "
            "it a lens): it is ignored");
    }
    if (camera.aperture > 0.0 && !(camera.focusDistance > 0.0)) {
        camera.focusDistance =
            std::max(1e-6, glm::dot(glm::dvec3(scene.bounds.center()) - camera.position, camera.forward));
    }
    // A lens far larger than the scene and the focus distance cannot be aimed in single precision: the GPU's
    // rays from a lens of radius 1e10 missed the scene the CPU's met (a brighter, wrong image, without a
    // word).
    const double reach = std::max({camera.focusDistance, glm::length(glm::dvec3(scene.bounds.extent())),
                                   glm::length(glm::dvec3(scene.bounds.center()) - camera.position)});
    if (camera.aperture > kMaxApertureOverScene * reach) {
        char message[256];
        std::snprintf(
            message, sizeof message,
            "the lens radius %.3g is more than %.0e times the largest of the scene's size, its distance "
            "and the focus distance (%.3g): its rays cannot be aimed in single precision",
            camera.aperture, kMaxApertureOverScene, reach);
        throw SceneError(message);
    }

    // Ambient light: none under an environment (it lights the scene); a little in a lit scene; in a dark one,
    // enough to see it by.
    const bool lit = sceneHasLights(scene);
    const double ambient = scene.environment.present() ? kEnvironmentAmbient
                           : lit                       ? kLitSceneAmbient
                                                       : kUnlitSceneAmbient;
    settings.ambient = paths ? glm::dvec3(0.0) : request.ambient.value_or(glm::dvec3(ambient));
    if (paths && request.ambient) {
        // addNeutralEnvironment made a uniform environment of it, unless a map was given.
        if (scene.environment.present() && !scene.environment.neutral) {
            setup.warnings.push_back("--ambient is Whitted's; paths under an environment map are lit by the map alone");
        }
    } else if (scene.environment.neutral) {
        setup.warnings.push_back(
            "the scene has no lights; a neutral environment (uniform radiance 1) lights it (--environment FILE "
            "or --ambient R,G,B light it otherwise)");
    } else if (!lit && !scene.environment.present() && !request.ambient) {
        setup.warnings.push_back(
            "the scene has no lights; an ambient radiance of 1 lights it (--environment FILE lights it with "
            "a map)");
    } else if (onlyTexturedEmission(scene) && !scene.environment.present() && !request.ambient) {
        // A model made for image-based lighting (DamagedHelmet) comes out nearly black, lit by its decals
        // alone.
        setup.warnings.push_back(
            "the scene's only lights are surfaces with emissive textures; if it looks dark, --environment "
            "FILE or "
            "--ambient R,G,B light it");
    }
    return setup;
}

bool onlyTexturedEmission(const Scene& scene) {
    if (!scene.lights.empty() || !scene.emissiveSpheres.empty() || !scene.emissiveShapes.empty() ||
        scene.emissiveTriangles.empty()) {
        return false;
    }
    return std::all_of(scene.emissiveTriangles.begin(), scene.emissiveTriangles.end(), [&](uint32_t t) {
        return scene.materials[scene.triangles[t].material].emissiveTexture.used();
    });
}

}  // namespace vkrt
