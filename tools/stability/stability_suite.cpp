#include "stability/stability_suite.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "app/render_policy.h"
#include "bvh/triangle_bvh.h"
#include "cpu/closest_hit.h"
#include "cpu/reference_renderer.h"
#include "cpu/triangle_intersection.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/gpu_renderer.h"
#include "image/image_metrics.h"
#include "random.h"
#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "support/reference_comparison.h"
#include "support/render_both.h"

namespace vkrt {
namespace {

using test::bvhFor;

struct Rendered {
    Image gpu, cpu;
    uint64_t nonFinite = 0;
};

Rendered renderBoth(const VulkanContext& context, const Scene& scene, const Camera& camera,
                    const RenderSettings& settings, const StabilityOptions& options) {
    const test::RenderPair pair =
        test::renderGpuAndCpu(context, scene, bvhFor(scene), camera, settings, options.shaderCacheDir);
    return {pair.gpu.image, pair.cpu.image, pair.gpu.rays.nonFiniteSamples + pair.cpu.rays.nonFiniteSamples};
}

StabilityResult measure(const StabilityOptions& options, const std::string& group, const std::string& name,
                        const Rendered& r) {
    if (!options.dumpDir.empty()) {
        std::string file = name;
        for (char& c : file) {
            if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+') c = '-';  // x1e-10 and x1e+10 apart
        }
        // FILE-image.pfm is the GPU's, FILE-reference.pfm the CPU reference's.
        test::writeComparisonImages(options.dumpDir, file, r.gpu, r.cpu);
    }
    StabilityResult result;
    result.group = group;
    result.name = name;
    result.nonFiniteSamples = r.nonFinite;
    const ImageDifference d = test::compareWithReference(r.gpu, r.cpu);
    result.gpuVsCpuOff = d.fractionOff;
    result.gpuVsCpuMeanRelative = d.meanRelativeError;
    return result;
}

void setInvariance(StabilityResult& result, const Image& image, const Image& reference) {
    const ImageDifference d = test::compareWithReference(image, reference);
    result.invarianceOff = d.fractionOff;
    result.invarianceMeanRelative = d.meanRelativeError;
}

// The glTF file at `path` with all its roots under one node that scales by `scale` and then translates;
// punctual intensities are multiplied by scale^2 so that irradiance stays the same, and volumes' attenuation
// distances (KHR_materials_volume, in world units) by scale so that their transmittance does.
Scene transformedVariant(const std::filesystem::path& path, double scale, double translation,
                         const std::filesystem::path& workDir, const std::string& name) {
    std::ifstream in(path);
    nlohmann::json gltf = nlohmann::json::parse(in);
    const int scene = gltf.value("scene", 0);
    nlohmann::json wrapper = {{"name", "stability transform"},
                              {"scale", {scale, scale, scale}},
                              {"translation", {translation, translation, translation}},
                              {"children", gltf["scenes"][scene]["nodes"]}};
    gltf["nodes"].push_back(wrapper);
    gltf["scenes"][scene]["nodes"] = {gltf["nodes"].size() - 1};
    if (gltf.contains("extensions") && gltf["extensions"].contains("KHR_lights_punctual")) {
        for (auto& light : gltf["extensions"]["KHR_lights_punctual"]["lights"]) {
            if (light.value("type", "") != "directional")
                light["intensity"] = light.value("intensity", 1.0) * scale * scale;
        }
    }
    if (gltf.contains("materials")) {
        for (auto& material : gltf["materials"]) {
            if (material.contains("extensions") && material["extensions"].contains("KHR_materials_volume")) {
                auto& volume = material["extensions"]["KHR_materials_volume"];
                if (volume.contains("attenuationDistance"))
                    volume["attenuationDistance"] = volume["attenuationDistance"].get<double>() * scale;
            }
        }
    }
    const std::filesystem::path file = workDir / (name + ".gltf");
    std::ofstream(file) << gltf.dump();
    return loadGltf(file.string());
}

Camera lookAt(glm::dvec3 eye, glm::dvec3 target, double yfov) {
    Camera camera = lookAtCamera(eye, target, yfov);
    camera.name = "stability";
    return camera;
}

Material diffuse(glm::vec3 color) {
    Material m;
    m.baseColor = glm::vec4(color, 1.0f);
    m.metallic = 0.0f;
    return m;
}

Material glass(float ior) {
    Material m = diffuse(glm::vec3(1.0f));
    m.roughness = 0.0f;
    m.transmission = 1.0f;
    m.ior = ior;
    m.thickness = 1.0f;
    return m;
}

// A 20 x 20 checkerboard at y = 0 (materials 0 and 1) lit by a point light.
Scene checkerboard() {
    Scene scene;
    scene.materials = {diffuse({0.8f, 0.75f, 0.1f}), diffuse({0.8f, 0.1f, 0.05f})};
    const int cells = 20;
    for (int i = 0; i < cells; ++i) {
        for (int j = 0; j < cells; ++j) {
            const float x = -10.0f + i, z = -10.0f + j;
            addFlatQuad(scene, {x, 0, z}, {x, 0, z + 1}, {x + 1, 0, z + 1}, {x + 1, 0, z}, (i + j) % 2);
        }
    }
    PunctualLight light;
    light.position = {2.0, 6.0, 3.0};
    light.intensity = 40.0f;
    scene.lights.push_back(light);
    return scene;
}

void addMesh(Scene& scene, const std::vector<Triangle>& triangles, uint32_t material, bool smooth,
             glm::vec3 center = glm::vec3(0.0f)) {
    for (const Triangle& t : triangles) {
        const glm::vec3 n = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
        if (!(glm::length(n) > 0.0f)) continue;  // the loader drops zero-area triangles too
        addFlatTriangle(scene, t.v0, t.v1, t.v2, material);
        if (smooth) {
            TriangleShading& s = scene.shading.back();
            s.normal[0] = glm::normalize(t.v0 - center);
            s.normal[1] = glm::normalize(t.v1 - center);
            s.normal[2] = glm::normalize(t.v2 - center);
        }
    }
}

RenderSettings settingsFor(const StabilityOptions& options) {
    RenderSettings settings;
    settings.width = options.width;
    settings.height = options.height;
    settings.samplesPerPixel = options.samplesPerPixel;
    settings.background = glm::dvec3(0.3, 0.45, 0.7);
    return settings;
}

// Scale and distance from the origin: the image must not change.
void invarianceCases(const VulkanContext& context, const StabilityOptions& options,
                     std::vector<StabilityResult>& results) {
    for (const char* sceneName : {"cornell", "whitted"}) {
        const std::filesystem::path path = options.sourceDir / "scenes" / (std::string(sceneName) + ".gltf");
        // The scene's own camera and the command's defaults for everything the options leave open.
        RenderRequest request;
        request.settings = settingsFor(options);
        request.height = options.height;
        const Scene unit =
            transformedVariant(path, 1.0, 0.0, options.workDir, std::string(sceneName) + "-unit");
        const RenderSetup unitSetup = resolveRender(request, unit);
        const Rendered reference = renderBoth(context, unit, unitSetup.camera, unitSetup.settings, options);
        results.push_back(measure(options, "scale", std::string(sceneName) + " x1", reference));
        for (double scale : {1e-10, 1e-5, 1e-3, 1e3, 1e6, 1e10}) {
            std::ostringstream name;
            name << sceneName << " x" << scale;
            const Scene scene = transformedVariant(path, scale, 0.0, options.workDir, name.str());
            const RenderSetup setup = resolveRender(request, scene);
            const Rendered r = renderBoth(context, scene, setup.camera, setup.settings, options);
            StabilityResult result = measure(options, "scale", name.str(), r);
            setInvariance(result, r.gpu, reference.gpu);
            results.push_back(result);
        }
        for (double offset : {1e3, 1e5, 1e6}) {
            std::ostringstream name;
            name << sceneName << " +" << offset;
            const Scene scene = transformedVariant(path, 1.0, offset, options.workDir, name.str());
            const RenderSetup setup = resolveRender(request, scene);
            const Rendered r = renderBoth(context, scene, setup.camera, setup.settings, options);
            StabilityResult result = measure(options, "far from origin", name.str(), r);
            setInvariance(result, r.gpu, reference.gpu);
            results.push_back(result);
        }
    }
}

// Camera rays nearly parallel to a plane lit by a directional light: every pixel that sees the plane must
// show the closed-form radiance (albedo / pi + F0 lobe) E cos(theta); darker pixels are shadow acne.
StabilityResult grazingPlane(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene;
    Material floor = diffuse(glm::vec3(0.5f));
    floor.ior = 1.0f;  // no specular term: exactly Lambertian
    scene.materials.push_back(floor);
    addFlatQuad(scene, {-1e4f, 0, -1e4f}, {-1e4f, 0, 1e4f}, {1e4f, 0, 1e4f}, {1e4f, 0, -1e4f}, 0);
    PunctualLight sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::dvec3(0.3, -1.0, -0.5));
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    finalizeScene(scene);
    RenderSettings settings = settingsFor(options);
    settings.ambient = glm::dvec3(0.0);
    settings.background = glm::dvec3(0.0);
    // 1 mm above the plane, looking down by 0.0101 rad with a field of view of 0.02 rad: every camera ray
    // meets the plane at 1e-4 to 2e-2 rad, 0.05 to 10 units away, and no pixel straddles the horizon.
    const Camera camera = lookAt({0.0, 1e-3, 0.0}, {0.0, 1e-3 - std::tan(0.0101), -1.0}, 0.02);
    const Rendered r = renderBoth(context, scene, camera, settings, options);
    StabilityResult result = measure(options, "grazing", "camera 0.001 above a plane", r);
    const double expected = 0.5 / M_PI * 2.0 * -sun.direction.y;
    size_t lit = 0, dark = 0;
    for (const Image* image : {&r.gpu, &r.cpu}) {
        for (const glm::vec3& p : image->pixels) {
            if (p.x == 0.0f) continue;  // sky
            ++lit;
            if (std::abs(p.x - expected) > 0.01 * expected) ++dark;
        }
    }
    result.acne = lit > 0 ? static_cast<double>(dark) / lit : 1.0;
    return result;
}

// A point light just above a surface.
StabilityResult lightAboveSurface(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.lights[0].position = {0.5, 1e-4, 0.5};
    scene.lights[0].intensity = 1e-3f;
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.5, 2.0, 3.0}, {0.5, 0.0, 0.5}, 0.7),
                                  settingsFor(options), options);
    return measure(options, "grazing", "point light 1e-4 above a plane", r);
}

// A coarse smooth-shaded sphere lit from the side: the shadow-terminator problem.
StabilityResult terminator(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.materials.push_back(diffuse(glm::vec3(0.8f)));
    addMesh(scene, makeUvSphere({0.0f, 1.0f, 0.0f}, 1.0f, 6, 12, 2), 2, true, {0.0f, 1.0f, 0.0f});
    scene.lights[0].position = {6.0, 1.0, 0.0};
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 1.5, 5.0}, {0.0, 1.0, 0.0}, 0.6),
                                  settingsFor(options), options);
    return measure(options, "grazing", "terminator: coarse smooth sphere", r);
}

StabilityResult thinSlab(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.materials.push_back(glass(1.5f));
    const float h = 1.0f, t = 1e-4f;
    addFlatQuad(scene, {-2, h + t, -2}, {-2, h + t, 2}, {2, h + t, 2}, {2, h + t, -2}, 2);  // top, facing up
    addFlatQuad(scene, {-2, h, -2}, {2, h, -2}, {2, h, 2}, {-2, h, 2}, 2);  // bottom, facing down
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 3.0, 3.0}, {0.0, 0.0, 0.0}, 0.8),
                                  settingsFor(options), options);
    return measure(options, "thin media", "glass slab 1e-4 thick", r);
}

// A blue quad over the board, `height` above it. Within a tie's width (VKRT_TIE_EPSILON, about 1e-6 times
// the distance) the board, first in the scene, wins the tie, and the rays that leave it must clear the quad
// it won over: the image must be the coincident one's. (The CPU reference's rays once started 1e-9 off the
// board, below the quad, which then shadowed the whole overlap: 71% of the pixels off.)
Scene boardUnderQuad(float height) {
    Scene scene = checkerboard();
    scene.materials.push_back(diffuse({0.1f, 0.3f, 0.9f}));
    addFlatQuad(scene, {-3, height, -3}, {-3, height, 3}, {3, height, 3}, {3, height, -3}, 2);
    finalizeScene(scene);
    return scene;
}

StabilityResult coincidentFaces(const VulkanContext& context, const StabilityOptions& options) {
    const Rendered r =
        renderBoth(context, boardUnderQuad(0.0f), lookAt({0.0, 3.0, 5.0}, {0.0, 0.0, 0.0}, 0.8),
                   settingsFor(options), options);
    return measure(options, "thin media", "coincident faces", r);
}

StabilityResult nearlyCoincidentFaces(const VulkanContext& context, const StabilityOptions& options) {
    const Camera camera = lookAt({0.0, 3.0, 5.0}, {0.0, 0.0, 0.0}, 0.8);
    const Rendered r = renderBoth(context, boardUnderQuad(1e-6f), camera, settingsFor(options), options);
    StabilityResult result = measure(options, "thin media", "faces 1e-6 apart (a tie)", r);
    const Rendered coincident =
        renderBoth(context, boardUnderQuad(0.0f), camera, settingsFor(options), options);
    setInvariance(result, r.cpu, coincident.cpu);
    return result;
}

// Spheres are tessellated (64 x 128 smooth-shaded triangles) or analytic (VKRT_sphere).
enum class SphereKind { Mesh, Analytic };

void addSphere(Scene& scene, glm::vec3 center, float radius, uint32_t material, SphereKind kind) {
    if (kind == SphereKind::Analytic) {
        scene.spheres.push_back({center, radius, material});
    } else {
        addMesh(scene, makeUvSphere(center, radius, 64, 128, material), material, true, center);
    }
}

const char* groupOf(SphereKind kind) {
    return kind == SphereKind::Analytic ? "analytic spheres" : "thin media";
}

// A sphere of `material` over the checkerboard; with `invariance`, compared with the board alone (for
// materials that must be invisible).
StabilityResult sphereCase(const VulkanContext& context, const StabilityOptions& options,
                           const Material& material, const std::string& name, SphereKind kind,
                           bool invariance = false) {
    const Camera camera = lookAt({0.0, 2.0, 5.0}, {0.0, 0.8, 0.0}, 0.7);
    auto build = [&](bool withSphere) {
        Scene scene = checkerboard();
        scene.materials.push_back(material);
        if (withSphere) addSphere(scene, {0.0f, 1.0f, 0.0f}, 1.0f, 2, kind);
        finalizeScene(scene);
        return scene;
    };
    const Rendered r = renderBoth(context, build(true), camera, settingsFor(options), options);
    StabilityResult result = measure(options, groupOf(kind), name, r);
    if (invariance) {
        const Rendered plain = renderBoth(context, build(false), camera, settingsFor(options), options);
        setInvariance(result, r.gpu, plain.gpu);
    }
    return result;
}

// Glass inside water: a sphere of index `innerIor`, off-centre inside a water sphere (1.33). With the right
// relative index at each interface an inner sphere of index 1.33 disappears, which the invariance columns
// check against the water sphere alone.
StabilityResult nestedDielectrics(const VulkanContext& context, const StabilityOptions& options,
                                  float innerIor, const std::string& name, SphereKind kind) {
    const Camera camera = lookAt({0.0, 2.0, 5.0}, {0.0, 1.0, 0.0}, 0.7);
    auto build = [&](bool inner) {
        Scene scene = checkerboard();
        scene.materials.push_back(glass(1.33f));
        addSphere(scene, {0.0f, 1.1f, 0.0f}, 1.1f, 2, kind);
        if (inner) {
            scene.materials.push_back(glass(innerIor));
            addSphere(scene, {0.2f, 1.1f, 0.1f}, 0.6f, 3, kind);
        }
        finalizeScene(scene);
        return scene;
    };
    const Rendered r = renderBoth(context, build(true), camera, settingsFor(options), options);
    StabilityResult result = measure(options, groupOf(kind), name, r);
    if (innerIor == 1.33f) {
        const Rendered water = renderBoth(context, build(false), camera, settingsFor(options), options);
        setInvariance(result, r.gpu, water.gpu);
    }
    return result;
}

// The cases Ray Tracing Gems ch. 7 is about: a sphere a hundred thousand times smaller than its distance
// from the camera, and a huge sphere used as the ground, where the textbook quadratic loses every digit.
StabilityResult distantSphere(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene;
    scene.materials.push_back(diffuse(glm::vec3(0.8f)));
    scene.spheres.push_back({{0.0f, 0.0f, 0.0f}, 1e-2f, 0});
    PunctualLight light;
    light.position = {-1e3, 1e3, 1e3};
    light.intensity = 3e6f;
    scene.lights.push_back(light);
    finalizeScene(scene);
    // 1000 units away, the sphere (radius 0.01) spans 2e-5 rad; the view is 3e-5 rad high.
    const Camera camera = lookAt({0.0, 0.0, 1e3}, {0.0, 0.0, 0.0}, 3e-5);
    const Rendered r = renderBoth(context, scene, camera, settingsFor(options), options);
    return measure(options, "analytic spheres", "radius 0.01 seen from 1000", r);
}

StabilityResult hugeGroundSphere(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene;
    scene.materials = {diffuse({0.8f, 0.75f, 0.1f}), diffuse({0.2f, 0.4f, 0.8f})};
    scene.spheres.push_back({{0.0f, -1e5f, 0.0f}, 1e5f, 0});
    for (int i = 0; i < 5; ++i) scene.spheres.push_back({{-2.0f + i, 0.3f, 0.0f}, 0.3f, 1});
    PunctualLight light;
    light.position = {2.0, 6.0, 3.0};
    light.intensity = 40.0f;
    scene.lights.push_back(light);
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 1.5, 5.0}, {0.0, 0.3, 0.0}, 0.7),
                                  settingsFor(options), options);
    return measure(options, "analytic spheres", "ground sphere of radius 1e5", r);
}

// A ball resting on a flat ground of two triangles 2e5 units across, both glTF's default material (rough
// white metal), under a uniform sky: the GPU's watertight test puts such a triangle's distance off by float
// epsilon times its corners' distance from the ray (about 0.01 here), which ray.glsl's hitPoint computes
// again in double (0.56% of the pixels around the contact were off without it).
StabilityResult hugeGroundQuad(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene;
    scene.materials = {Material{}, Material{}};  // glTF's default: a rough white metal
    const float h = 1e5f;
    addFlatTriangle(scene, {-h, 0.0f, -h}, {-h, 0.0f, h}, {h, 0.0f, h}, 0);
    addFlatTriangle(scene, {-h, 0.0f, -h}, {h, 0.0f, h}, {h, 0.0f, -h}, 0);
    scene.spheres.push_back({{0.0f, 0.5f, 0.0f}, 0.5f, 1});
    finalizeScene(scene);
    RenderSettings settings = settingsFor(options);
    settings.ambient = glm::dvec3(1.0);  // paths: a uniform environment of radiance 1
    const Rendered r =
        renderBoth(context, scene, lookAt({0.0, 1.0, 4.0}, {0.0, 0.4, 0.0}, 0.8), settings, options);
    return measure(options, "degenerate", "ball on a ground of two triangles 2e5 across", r);
}

StabilityResult degenerateGeometry(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.materials.push_back(diffuse(glm::vec3(0.7f)));
    // Slivers of aspect 1e6, 100k coincident triangles, and huge triangles beside tiny ones.
    for (int i = 0; i < 50; ++i) {
        const float x = -2.5f + 0.1f * i;
        addFlatTriangle(scene, {x, 0.5f, 0.0f}, {x + 1e-6f, 0.5f, 0.0f}, {x, 1.5f, 0.0f}, 2);
    }
    for (int i = 0; i < 100000; ++i)
        addFlatTriangle(scene, {1.0f, 0.2f, 0.5f}, {2.0f, 0.2f, 0.5f}, {1.5f, 1.2f, 0.5f}, 2);
    addFlatTriangle(scene, {-1e5f, -1.0f, -1e5f}, {1e5f, -1.0f, -1e5f}, {0.0f, -1.0f, 1e5f}, 2);
    for (int i = 0; i < 1000; ++i) {
        const glm::vec3 p(-1.0f + 0.002f * i, 0.3f, 1.0f);
        addFlatTriangle(scene, p, p + glm::vec3(1e-5f, 0, 0), p + glm::vec3(0, 1e-5f, 0), 2);
    }
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 2.0, 5.0}, {0.0, 0.5, 0.0}, 0.8),
                                  settingsFor(options), options);
    return measure(options, "degenerate", "slivers, 100k coincident, huge beside tiny", r);
}

// Rays aimed exactly at the vertices and edge midpoints of closed meshes, from outside: each must hit.
StabilityResult watertightness(const VulkanContext& context, const StabilityOptions& options, bool cube) {
    Scene scene;
    scene.materials.push_back(diffuse(glm::vec3(0.5f)));
    if (cube) {
        // A cube whose faces are split into 40 x 40 quads.
        const int n = 40;
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                for (int i = 0; i < n; ++i) {
                    for (int j = 0; j < n; ++j) {
                        auto corner = [&](int a, int b) {
                            glm::vec3 p;
                            p[axis] = side ? 1.0f : -1.0f;
                            p[(axis + 1) % 3] = -1.0f + 2.0f * a / n;
                            p[(axis + 2) % 3] = -1.0f + 2.0f * b / n;
                            return p;
                        };
                        addFlatQuad(scene, corner(i, j), corner(i + 1, j), corner(i + 1, j + 1),
                                    corner(i, j + 1), 0);
                    }
                }
            }
        }
    } else {
        addMesh(scene, makeUvSphere(glm::vec3(0.0f), 1.0f, 100, 200), 0, false);
    }
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    std::vector<gpu::GpuRay> rays;
    uint32_t i = 0;
    for (const Triangle& t : scene.triangles) {
        for (const glm::vec3& target : {t.v0, 0.5f * (t.v0 + t.v1), 0.5f * (t.v1 + t.v2)}) {
            // From a point outside, through the vertex or edge towards the inside.
            const glm::vec3 jitter(vkrtRandom(5, i, 0, 0) - 0.5f, vkrtRandom(5, i, 0, 1) - 0.5f,
                                   vkrtRandom(5, i, 0, 2) - 0.5f);
            ++i;
            const glm::vec3 origin = 3.0f * glm::normalize(target + 0.3f * jitter);
            rays.push_back({origin, 0.0f, glm::normalize(target - origin), 1e30f});
        }
    }
    GpuRaycaster raycaster(context, scene, bvh, options.shaderCacheDir);
    const std::vector<gpu::GpuHit> hits = raycaster.trace(rays, RaycastMode::Closest);
    StabilityResult result;
    result.group = "watertightness";
    result.name = cube ? "cube of 19,200 triangles" : "sphere of 39,600 triangles";
    uint64_t leaks = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        if (hits[k].primitive == VKRT_NO_HIT) ++leaks;
        // The CPU reference must not leak either.
        const RayT<double> ray{glm::dvec3(rays[k].origin), glm::dvec3(rays[k].direction)};
        SurfaceHit hit;
        if (!closestHit(scene, bvh, ray, 1e30, kNoPrimitive, hit)) ++leaks;
    }
    result.leaks = leaks;
    return result;
}

StabilityResult extremeEmission(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.lights.clear();
    Material lamp = diffuse(glm::vec3(0.0f));
    lamp.emission = glm::vec3(1e6f);
    scene.materials.push_back(lamp);
    const float s = 1e-3f;  // a 1 mm emitter, facing down
    addFlatQuad(scene, {-s, 1.0f, -s}, {s, 1.0f, -s}, {s, 1.0f, s}, {-s, 1.0f, s}, 2);
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, 0.8),
                                  settingsFor(options), options);
    return measure(options, "extreme values", "emission 1e6 from a 2 mm light", r);
}

StabilityResult blackMaterials(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    for (Material& m : scene.materials) m.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    finalizeScene(scene);
    RenderSettings settings = settingsFor(options);
    const Rendered r =
        renderBoth(context, scene, lookAt({0.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, 0.8), settings, options);
    return measure(options, "extreme values", "black materials", r);
}

StabilityResult roughnessExtremes(const VulkanContext& context, const StabilityOptions& options,
                                  float roughness) {
    Material metal = diffuse(glm::vec3(0.9f));
    metal.metallic = 1.0f;
    metal.roughness = roughness;
    std::ostringstream name;
    name << "metal sphere, roughness " << roughness;
    StabilityResult result = sphereCase(context, options, metal, name.str(), SphereKind::Mesh);
    result.group = "extreme values";
    return result;
}

// Many samples of a constant: a lone emissive quad filling the view. The mean must stay exact.
StabilityResult longAccumulation(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene;
    Material glow = diffuse(glm::vec3(0.0f));
    glow.emission = glm::vec3(0.3f);
    scene.materials.push_back(glow);
    addFlatQuad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
    finalizeScene(scene);
    RenderSettings settings;
    settings.width = settings.height = 4;
    settings.samplesPerPixel = options.longAccumulationSamples;
    settings.ambient = glm::dvec3(0.0);
    const FlatBvh bvh = bvhFor(scene);
    GpuRenderOptions gpuOptions;
    gpuOptions.shaderCacheDir = options.shaderCacheDir;
    GpuRenderer renderer(context, scene, bvh, lookAt({0.0, 0.0, 5.0}, {0.0, 0.0, 0.0}, 0.5), settings,
                         gpuOptions);
    const RenderResult r = renderer.render();
    StabilityResult result;
    result.group = "extreme values";
    std::ostringstream name;
    name << options.longAccumulationSamples << " samples of a constant 0.3";
    result.name = name.str();
    result.nonFiniteSamples = r.rays.nonFiniteSamples;
    double worst = 0.0;
    for (const glm::vec3& p : r.image.pixels)
        worst = std::max(worst, std::abs(p.x / static_cast<double>(0.3f) - 1.0));
    result.accumulationError = worst;
    return result;
}

// ---------------------------------------------------------------------------------------------------------------
// Analytic shapes and CSG (VKRT_shape, VKRT_csg, docs/vkrt_shape.md), ray by ray on both devices: grazing
// rays, rays through edges, corners and the apex, operands with coincident faces, and huge and tiny scales.

// One ray's answer: a miss, or a hit at t; on a solid, the scene's shape and face * 2 + flip.
struct RayAnswer {
    bool hit = false;
    double t = 0.0;
    uint32_t primitive = VKRT_NO_HIT;
    uint32_t shape = 0, face = 0;
};

constexpr uint32_t kAnyShape = 0xffffffffu;

// What a ray must meet: nothing, or a hit at about `t` (NaN: wherever the CPU reference finds it) whose
// surface makes cosine `cosine` with the ray (NaN: the CPU's hit's), on shape `shape` (kAnyShape: any) and
// face `face` (as hits encode it: face * 2 + flip); never on the faces `forbidden` ((shape, face * 2 + flip):
// faces inside the solid).
struct Expected {
    bool hit = false;
    double t = std::numeric_limits<double>::quiet_NaN();
    double cosine = std::numeric_limits<double>::quiet_NaN();
    uint32_t shape = kAnyShape, face = 0;
    std::vector<std::pair<uint32_t, uint32_t>> forbidden;
};

Expected mustMiss() {
    return Expected{};
}

Expected mustHit(double t = std::numeric_limits<double>::quiet_NaN(), uint32_t shape = kAnyShape,
                 uint32_t face = 0, double cosine = std::numeric_limits<double>::quiet_NaN()) {
    Expected e;
    e.hit = true;
    e.t = t;
    e.shape = shape;
    e.face = face;
    e.cosine = cosine;
    return e;
}

// The expectation of an answer found on a reference scene (the same solid without the coincident faces, or
// the unit-scale scene): the same hit or miss, at the same distance (times `scale`), on the same face when
// `sameFace`.
Expected expectedFrom(const RayAnswer& reference, double cosine, bool sameFace, double scale = 1.0) {
    Expected e;
    e.hit = reference.hit;
    e.t = reference.t * scale;
    e.cosine = cosine;
    if (sameFace) {
        e.shape = reference.shape;
        e.face = reference.face;
    }
    return e;
}

// |cos| between a ray and the surface's normal where it hits a solid (1 for other primitives and misses).
double hitCosine(const Scene& scene, const RayAnswer& answer, const RayT<double>& ray) {
    if (!answer.hit || !scene.isSolid(answer.primitive)) return 1.0;
    const Shape& shape = scene.shapes[answer.shape];
    const shading::ShapePoint p =
        shading::shapePoint(shape.type, answer.face / 2u, false, shading::affineRows(shape.toObject),
                            ray.origin, ray.direction, answer.t);
    return std::abs(glm::dot(p.normal, glm::normalize(ray.direction)));
}

struct Answers {
    std::vector<RayAnswer> gpu, cpu;
};

// The problems of a ray case, counted by kind (which device, what went wrong, on which kind of shape), and
// the first one described: the case's note.
struct Tally {
    std::map<std::string, uint64_t> counts;
    std::string first;

    void add(const std::string& kind, const std::function<std::string()>& describeFirst) {
        ++counts[kind];
        if (first.empty()) first = describeFirst();
    }
    std::string note() const {
        if (counts.empty()) return "";
        std::ostringstream s;
        bool comma = false;
        for (const auto& [kind, count] : counts) {
            s << (comma ? ", " : "") << count << " x " << kind;
            comma = true;
        }
        s << ". First: " << first;
        return s.str();
    }
};

const char* shapeName(uint32_t type) {
    return type == VKRT_SHAPE_SPHERE     ? "sphere"
           : type == VKRT_SHAPE_BOX      ? "box"
           : type == VKRT_SHAPE_CYLINDER ? "cylinder"
                                         : "cone";
}

// The kind of shape a ray's answer (else the reference's) names, for tallies.
std::string shapeOf(const Scene& scene, const RayAnswer& answer, const RayAnswer& reference) {
    const RayAnswer& a = answer.hit && scene.isSolid(answer.primitive) ? answer : reference;
    if (!a.hit || !scene.isSolid(a.primitive) || a.shape >= scene.shapes.size()) return "";
    return std::string(" (") + shapeName(scene.shapes[a.shape].type) + ")";
}

// The rays' closest hits in (tMin, tMax) on the GPU (float) and the CPU reference (double).
Answers traceBoth(const VulkanContext& context, const StabilityOptions& options, const Scene& scene,
                  const std::vector<gpu::GpuRay>& rays) {
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster raycaster(context, scene, bvh, options.shaderCacheDir);
    const std::vector<gpu::GpuHit> hits = raycaster.trace(rays, RaycastMode::Closest);
    Answers answers;
    for (size_t i = 0; i < rays.size(); ++i) {
        RayAnswer gpu;
        if (hits[i].primitive != VKRT_NO_HIT) {
            gpu = {true, hits[i].t, hits[i].primitive, 0u, 0u};
            if (scene.isSolid(hits[i].primitive)) {
                gpu.shape = static_cast<uint32_t>(hits[i].u);
                gpu.face = static_cast<uint32_t>(hits[i].v);
            }
        }
        answers.gpu.push_back(gpu);
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        SurfaceHit hit;
        RayAnswer cpu;
        if (closestHitBeyond(scene, bvh, ray, rays[i].tMin, rays[i].tMax, kNoPrimitive, hit)) {
            cpu = {true, hit.t, hit.primitive, 0u, 0u};
            if (scene.isSolid(hit.primitive)) {
                cpu.shape = static_cast<uint32_t>(hit.u);
                cpu.face = static_cast<uint32_t>(hit.v);
            }
        }
        answers.cpu.push_back(cpu);
    }
    return answers;
}

std::string describe(const RayAnswer& a) {
    if (!a.hit) return "a miss";
    std::ostringstream s;
    s << std::setprecision(9) << "a hit at t " << a.t << " (shape " << a.shape << ", face " << a.face / 2
      << (a.face % 2 ? ", flipped" : "") << ")";
    return s.str();
}

std::string describe(const gpu::GpuRay& r) {
    std::ostringstream s;
    s << std::setprecision(9) << "origin (" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z
      << "), direction (" << r.direction.x << ", " << r.direction.y << ", " << r.direction.z << ")";
    return s.str();
}

// Both devices' answers against the expectations: a miss where a hit was due is a leak; a hit where none was
// due, at another distance (1e-5 relative along the surface's normal, plus 1e-6 of `size`), on another face
// or on a forbidden one is wrong. The first failure is described in the result's note.
StabilityResult judgeRays(const std::string& group, const std::string& name, const Scene& scene,
                          const std::vector<gpu::GpuRay>& rays, const Answers& answers,
                          const std::vector<Expected>& expected, double size) {
    StabilityResult result;
    result.group = group;
    result.name = name;
    uint64_t leaks = 0, wrong = 0;
    Tally tally;
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        const Expected& e = expected[i];
        for (const bool onGpu : {true, false}) {
            const RayAnswer& got = onGpu ? answers.gpu[i] : answers.cpu[i];
            std::string problem;
            if (e.hit && !got.hit) {
                ++leaks;
                problem = "leaks";
            } else if (!e.hit && got.hit) {
                ++wrong;
                problem = "hits where nothing is";
            } else if (got.hit) {
                const double t = std::isnan(e.t) ? answers.cpu[i].t : e.t;
                const double cosine = std::isnan(e.cosine) ? hitCosine(scene, answers.cpu[i], ray) : e.cosine;
                if (std::abs(got.t - t) * cosine > 1e-5 * t + 1e-6 * size) {
                    problem = "hits at another distance";
                } else if (e.shape != kAnyShape && (got.shape != e.shape || got.face != e.face)) {
                    problem = "hits another face";
                } else if (std::find(e.forbidden.begin(), e.forbidden.end(),
                                     std::make_pair(got.shape, got.face)) != e.forbidden.end()) {
                    problem = "hits a face inside the solid";
                }
                if (!problem.empty()) ++wrong;
            }
            if (problem.empty()) continue;
            tally.add(std::string(onGpu ? "GPU " : "CPU ") + problem + shapeOf(scene, got, answers.cpu[i]),
                      [&] {
                          std::ostringstream s;
                          s << (onGpu ? "GPU" : "CPU") << " ray " << i << " " << problem << ": "
                            << describe(got) << "; expected " << (e.hit ? "a hit" : "a miss");
                          if (e.hit && !std::isnan(e.t)) s << std::setprecision(9) << " at t " << e.t;
                          if (e.hit && e.shape != kAnyShape)
                              s << " on shape " << e.shape << " face " << e.face / 2;
                          s << "; CPU: " << describe(answers.cpu[i]) << "; " << describe(rays[i]);
                          return s.str();
                      });
        }
    }
    result.leaks = leaks;
    result.wrongHits = wrong;
    result.note = tally.note();
    return result;
}

// The place of the shapes of these cases: a turn about a tilted axis and a non-uniform scale.
glm::dmat4 shapeFrame() {
    return glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 0.1)) *
           glm::rotate(glm::dmat4(1.0), glm::radians(35.0), glm::normalize(glm::dvec3(1.0, 2.0, 0.5))) *
           glm::scale(glm::dmat4(1.0), glm::dvec3(1.2, 0.5, 0.8));
}

glm::dvec3 mapPoint(const glm::dmat4& m, glm::dvec3 p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

glm::dvec3 mapVector(const glm::dmat4& m, glm::dvec3 v) {
    return glm::dvec3(m * glm::dvec4(v, 0.0));
}

// An object-space normal in the world (the inverse transpose), unit length.
glm::dvec3 mapNormal(const glm::dmat4& m, glm::dvec3 n) {
    return glm::normalize(glm::transpose(glm::inverse(glm::dmat3(m))) * n);
}

// A ray from world point `origin` to world point `target` (float, as the GPU takes it).
gpu::GpuRay rayThrough(glm::dvec3 origin, glm::dvec3 target) {
    const glm::vec3 o(origin), p(target);
    return {o, 0.0f, glm::normalize(p - o), 1e30f};
}

bool in(uint32_t state, int shape) {
    return ((state >> shape) & 1u) != 0u;
}

const std::array<uint32_t, 8> kAlone = truthTable(1, [](uint32_t s) { return in(s, 0); });

Scene solidScene(const std::vector<std::pair<std::vector<Shape>, std::array<uint32_t, 8>>>& solids) {
    Scene scene;
    scene.materials.push_back(diffuse(glm::vec3(0.5f)));
    for (const auto& [shapes, table] : solids) addSolid(scene, shapes, table);
    finalizeScene(scene);
    return scene;
}

// A random unit vector orthogonal to unit n.
glm::dvec3 tangentOf(glm::dvec3 n, double angle) {
    const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(n, a)), v = glm::cross(n, u);
    return std::cos(angle) * u + std::sin(angle) * v;
}

double random01(uint32_t stream, uint32_t i, uint32_t d) {
    return vkrtRandom(stream, i, 0, d);
}

// Grazing rays on a box (turned, scaled non-uniformly): rays descending onto each face at 1e-2 to 1e-5 rad
// from its plane, aimed at its inner part, hit that face where they aim; rays parallel to a face, 1e-3 or
// 1e-5 (object units) inside it, enter by the face across their path; as far outside, miss.
StabilityResult grazingBox(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    const Scene scene = solidScene({{{makeShape(VKRT_SHAPE_BOX, 0, m)}, kAlone}});
    std::vector<gpu::GpuRay> rays;
    std::vector<Expected> expected;
    uint32_t i = 0;
    for (uint32_t face = 0; face < 6; ++face) {
        const int axis = static_cast<int>(face / 2);
        glm::dvec3 n(0.0);
        n[axis] = face % 2 ? 1.0 : -1.0;
        const glm::dvec3 worldNormal = mapNormal(m, n);
        for (const double angle : {1e-2, 1e-3, 1e-4, 1e-5}) {
            for (int k = 0; k < 250; ++k, ++i) {
                glm::dvec3 p = n;
                p[(axis + 1) % 3] = 1.4 * random01(21, i, 0) - 0.7;
                p[(axis + 2) % 3] = 1.4 * random01(21, i, 1) - 0.7;
                const glm::dvec3 along = tangentOf(n, 2.0 * M_PI * random01(21, i, 2));
                const glm::dvec3 d =
                    glm::normalize(mapVector(m, std::cos(angle) * along - std::sin(angle) * n));
                const glm::dvec3 target = mapPoint(m, p);
                rays.push_back(rayThrough(target - 3.0 * d, target));
                const double t = glm::length(glm::dvec3(glm::vec3(target)) - glm::dvec3(rays.back().origin));
                expected.push_back(mustHit(t, 0u, 2u * face, std::abs(glm::dot(d, worldNormal))));
            }
        }
        // Parallel to the face, offset along its normal by -delta (inside: entering by the face the ray runs
        // towards, opposite its direction) or +delta (outside: nothing).
        for (const double delta : {1e-3, 1e-5}) {
            for (const double side : {-1.0, 1.0}) {
                for (int k = 0; k < 100; ++k, ++i) {
                    const int b = (axis + 1 + (k % 2)) % 3;  // the axis the ray runs along
                    const int c = 3 - axis - b;
                    glm::dvec3 start = n * (1.0 + side * delta), dir(0.0);
                    dir[b] = 1.0;
                    start[b] = -3.0;
                    start[c] = 1.6 * random01(22, i, 0) - 0.8;
                    const glm::dvec3 entry = glm::dvec3(start.x, start.y, start.z) + 2.0 * dir;  // at b = -1
                    const glm::dvec3 origin = mapPoint(m, start);
                    rays.push_back(rayThrough(origin, mapPoint(m, start + dir)));
                    if (side > 0) {
                        expected.push_back(mustMiss());
                    } else {
                        const glm::dvec3 faceNormal = mapNormal(m, -dir);
                        const double cosine =
                            std::abs(glm::dot(faceNormal, glm::dvec3(rays.back().direction)));
                        expected.push_back(
                            mustHit(glm::length(mapPoint(m, entry) - glm::dvec3(rays.back().origin)), 0u,
                                    4u * static_cast<uint32_t>(b), cosine));  // face 2b
                    }
                }
            }
        }
    }
    return judgeRays("shapes: grazing", "box: rays 1e-5 rad from its faces, and 1e-5 inside or outside them",
                     scene, rays, traceBoth(context, options, scene, rays), expected, 2.0);
}

// Grazing rays on a cylinder (turned, scaled non-uniformly: an elliptic cylinder): rays parallel to its axis
// 1e-3 or 1e-5 (object units) inside its side enter by the bottom cap, as far outside miss; rays across the
// axis tangent to the side, as far inside, hit the side, outside miss; rays descending onto the side at 1e-2
// to 1e-5 rad along its straight lines hit it where they aim.
StabilityResult grazingCylinder(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    const Scene scene = solidScene({{{makeShape(VKRT_SHAPE_CYLINDER, 0, m)}, kAlone}});
    std::vector<gpu::GpuRay> rays;
    std::vector<Expected> expected;
    uint32_t i = 0;
    for (const double delta : {1e-3, 1e-5}) {
        for (const double side : {-1.0, 1.0}) {
            const double rho = 1.0 + side * delta;
            for (int k = 0; k < 300; ++k, ++i) {
                const double phi = 2.0 * M_PI * random01(23, i, 0);
                const glm::dvec3 radial(std::cos(phi), 0.0, std::sin(phi));
                // Along the axis, from below.
                const glm::dvec3 start = rho * radial + glm::dvec3(0.0, -3.0, 0.0);
                rays.push_back(rayThrough(mapPoint(m, start), mapPoint(m, start + glm::dvec3(0, 1, 0))));
                if (side > 0) {
                    expected.push_back(mustMiss());
                } else {
                    const double t = glm::length(mapPoint(m, start + glm::dvec3(0, 2, 0)) -
                                                 glm::dvec3(rays.back().origin));
                    const double cosine =
                        std::abs(glm::dot(mapNormal(m, {0, -1, 0}), glm::dvec3(rays.back().direction)));
                    expected.push_back(mustHit(t, 0u, 2u * VKRT_FACE_BOTTOM, cosine));
                }
                // Across the axis, tangent to the side at height y.
                const double y = 1.6 * random01(23, i, 1) - 0.8;
                const glm::dvec3 along(-std::sin(phi), 0.0, std::cos(phi));
                const glm::dvec3 foot = rho * radial + glm::dvec3(0.0, y, 0.0);
                rays.push_back(rayThrough(mapPoint(m, foot - 3.0 * along), mapPoint(m, foot)));
                if (side > 0) {
                    expected.push_back(mustMiss());
                } else {
                    const glm::dvec3 entry = foot - std::sqrt(1.0 - rho * rho) * along;
                    const double t = glm::length(mapPoint(m, entry) - glm::dvec3(rays.back().origin));
                    const double cosine = std::abs(
                        glm::dot(mapNormal(m, {entry.x, 0.0, entry.z}), glm::dvec3(rays.back().direction)));
                    expected.push_back(mustHit(t, 0u, 2u * VKRT_FACE_SIDE, cosine));
                }
            }
        }
    }
    for (const double angle : {1e-2, 1e-3, 1e-4, 1e-5}) {
        for (int k = 0; k < 300; ++k, ++i) {
            const double phi = 2.0 * M_PI * random01(24, i, 0), y = 1.4 * random01(24, i, 1) - 0.7;
            const glm::dvec3 n(std::cos(phi), 0.0, std::sin(phi));
            // Along the side's straight line (up or down), tilted into the side: across the round way a chord
            // that shallow is thinner (angle^2 / 2) than a float's rounding, and may miss.
            const glm::dvec3 along(0.0, random01(24, i, 2) < 0.5 ? -1.0 : 1.0, 0.0);
            const glm::dvec3 d = glm::normalize(mapVector(m, std::cos(angle) * along - std::sin(angle) * n));
            const glm::dvec3 target = mapPoint(m, n + glm::dvec3(0.0, y, 0.0));
            rays.push_back(rayThrough(target - 0.5 * d, target));
            const double t = glm::length(glm::dvec3(glm::vec3(target)) - glm::dvec3(rays.back().origin));
            expected.push_back(mustHit(t, 0u, 2u * VKRT_FACE_SIDE, std::abs(glm::dot(d, mapNormal(m, n)))));
        }
    }
    return judgeRays("shapes: grazing", "cylinder: rays 1e-5 inside or outside its side, along and across it",
                     scene, rays, traceBoth(context, options, scene, rays), expected, 2.0);
}

// Rays along the rulings of a cone (turned, scaled non-uniformly), offset 1e-3 or 1e-5 (object units) from
// them: inside, upwards, they enter by the base; inside, downwards, by the side near the apex; outside they
// miss (they meet only the other nappe, beyond the apex). And rays descending onto the side at 1e-2 to 1e-5
// rad along the rulings hit it where they aim.
StabilityResult grazingCone(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    const Scene scene = solidScene({{{makeShape(VKRT_SHAPE_CONE, 0, m)}, kAlone}});
    std::vector<gpu::GpuRay> rays;
    std::vector<Expected> expected;
    uint32_t i = 0;
    const glm::dvec3 apex(0.0, 1.0, 0.0);
    for (const double delta : {1e-3, 1e-5}) {
        for (const double side : {-1.0, 1.0}) {
            for (int k = 0; k < 300; ++k, ++i) {
                const double phi = 2.0 * M_PI * random01(25, i, 0);
                const glm::dvec3 base(std::cos(phi), -1.0, std::sin(phi));
                const glm::dvec3 ruling = glm::normalize(apex - base);  // upwards
                const glm::dvec3 n =
                    glm::normalize(glm::dvec3(std::cos(phi), 0.5, std::sin(phi)));  // outward
                const glm::dvec3 offset = side * delta * n;
                // Upwards from below the base.
                const glm::dvec3 low = base + offset - 2.0 * ruling;
                rays.push_back(rayThrough(mapPoint(m, low), mapPoint(m, low + ruling)));
                if (side > 0) {
                    expected.push_back(mustMiss());
                } else {
                    const double s = (-1.0 - low.y) / ruling.y;  // where it crosses the base's plane
                    const double t =
                        glm::length(mapPoint(m, low + s * ruling) - glm::dvec3(rays.back().origin));
                    const double cosine =
                        std::abs(glm::dot(mapNormal(m, {0, -1, 0}), glm::dvec3(rays.back().direction)));
                    expected.push_back(mustHit(t, 0u, 2u * VKRT_FACE_BOTTOM, cosine));
                }
                // Downwards from above the apex.
                const glm::dvec3 high = apex + offset + 1.0 * ruling;
                rays.push_back(rayThrough(mapPoint(m, high), mapPoint(m, high - ruling)));
                expected.push_back(
                    side > 0 ? mustMiss()
                             : mustHit(std::numeric_limits<double>::quiet_NaN(), 0u, 2u * VKRT_FACE_SIDE));
            }
        }
    }
    for (const double angle : {1e-2, 1e-3, 1e-4, 1e-5}) {
        for (int k = 0; k < 300; ++k, ++i) {
            const double phi = 2.0 * M_PI * random01(26, i, 0), y = 1.2 * random01(26, i, 1) - 0.8;
            const glm::dvec3 radial(std::cos(phi), 0.0, std::sin(phi));
            const glm::dvec3 n = glm::normalize(radial + glm::dvec3(0.0, 0.5, 0.0));
            const glm::dvec3 p = 0.5 * (1.0 - y) * radial + glm::dvec3(0.0, y, 0.0);
            // Along the ruling (up or down), tilted into the side (across it, see grazingCylinder).
            const glm::dvec3 along = glm::normalize(glm::dvec3(-std::cos(phi), 2.0, -std::sin(phi))) *
                                     (random01(26, i, 2) < 0.5 ? -1.0 : 1.0);
            const glm::dvec3 d = glm::normalize(mapVector(m, std::cos(angle) * along - std::sin(angle) * n));
            const glm::dvec3 target = mapPoint(m, p);
            rays.push_back(rayThrough(target - 0.3 * d, target));
            const double t = glm::length(glm::dvec3(glm::vec3(target)) - glm::dvec3(rays.back().origin));
            expected.push_back(mustHit(t, 0u, 2u * VKRT_FACE_SIDE, std::abs(glm::dot(d, mapNormal(m, n)))));
        }
    }
    return judgeRays("shapes: grazing", "cone: rays 1e-5 inside or outside its rulings, and onto its side",
                     scene, rays, traceBoth(context, options, scene, rays), expected, 2.0);
}

// The sums of several ray cases' counts under one name (the first note kept).
StabilityResult combined(const std::string& group, const std::string& name,
                         const std::vector<StabilityResult>& parts) {
    StabilityResult result;
    result.group = group;
    result.name = name;
    uint64_t leaks = 0, wrong = 0;
    for (const StabilityResult& part : parts) {
        leaks += part.leaks.value_or(0);
        wrong += part.wrongHits.value_or(0);
        if (!part.note.empty())
            result.note += (result.note.empty() ? "" : "; ") + part.name + ": " + part.note;
    }
    result.leaks = leaks;
    result.wrongHits = wrong;
    return result;
}

// Rays through a point of an edge (or a corner, or the apex) of a closed solid, coming from outside in
// directions that enter the solid through every face meeting there (d . n < -0.1 for each outward normal n):
// through the point itself and through the point moved by one float ulp up or down each coordinate, from
// `distance` away. Each must hit, there: a ray through an edge may cross either face, never slip between.
struct EdgeRays {
    std::vector<gpu::GpuRay> rays;
    std::vector<Expected> expected;
    uint32_t stream = 0, count = 0;

    void add(glm::dvec3 point, const std::vector<glm::dvec3>& normals, double distance) {
        // A direction against the normals' sum, jittered, until it enters through every face.
        glm::dvec3 d(0.0);
        double worst = 0.0;
        for (int attempt = 0; attempt < 64; ++attempt, ++count) {
            glm::dvec3 sum(0.0);
            for (const glm::dvec3& n : normals) sum += n * (0.3 + random01(stream, count, 0));
            const glm::dvec3 jitter(random01(stream, count, 1) - 0.5, random01(stream, count, 2) - 0.5,
                                    random01(stream, count, 3) - 0.5);
            d = -glm::normalize(glm::normalize(sum) + 0.6 * jitter);
            worst = 0.0;
            for (const glm::dvec3& n : normals) worst = std::max(worst, glm::dot(d, n));
            if (worst < -0.1) break;
        }
        if (!(worst < -0.1)) return;
        const glm::vec3 target(point);
        for (int nudge = 0; nudge < 7; ++nudge) {
            glm::vec3 p = target;
            if (nudge > 0) {
                const int axis = (nudge - 1) / 2;
                p[axis] = std::nextafter(p[axis], nudge % 2 ? 1e30f : -1e30f);
            }
            const glm::vec3 origin(glm::dvec3(p) - distance * d);
            rays.push_back({origin, 0.0f, glm::normalize(p - origin), 1e30f});
            expected.push_back(
                mustHit(glm::length(glm::dvec3(p) - glm::dvec3(origin)), kAnyShape, 0u, -worst));
        }
    }
};

StabilityResult edgeCase(const VulkanContext& context, const StabilityOptions& options,
                         const std::string& name, const Scene& scene, const EdgeRays& edges) {
    return judgeRays("shapes: edges", name, scene, edges.rays, traceBoth(context, options, scene, edges.rays),
                     edges.expected, 2.0);
}

// The box's 12 edges and 8 corners, the cylinder's rims, the cone's rim and apex.
StabilityResult shapeEdges(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    std::vector<StabilityResult> parts;
    {
        EdgeRays edges{{}, {}, 31};
        for (int a = 0; a < 3; ++a) {
            for (const double sb : {-1.0, 1.0}) {
                for (const double sc : {-1.0, 1.0}) {
                    const int b = (a + 1) % 3, c = (a + 2) % 3;
                    glm::dvec3 nb(0.0), nc(0.0);
                    nb[b] = sb;
                    nc[c] = sc;
                    for (int k = 0; k < 24; ++k) {
                        glm::dvec3 p = nb + nc;
                        p[a] = -0.95 + 1.9 * (k + 0.5) / 24.0;
                        edges.add(mapPoint(m, p), {mapNormal(m, nb), mapNormal(m, nc)}, 0.5);
                    }
                }
            }
        }
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 s(corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0);
            for (int k = 0; k < 24; ++k) {
                edges.add(mapPoint(m, s),
                          {mapNormal(m, {s.x, 0, 0}), mapNormal(m, {0, s.y, 0}), mapNormal(m, {0, 0, s.z})},
                          0.5);
            }
        }
        parts.push_back(edgeCase(context, options, "box",
                                 solidScene({{{makeShape(VKRT_SHAPE_BOX, 0, m)}, kAlone}}), edges));
    }
    {
        EdgeRays edges{{}, {}, 32};
        for (const double y : {-1.0, 1.0}) {
            for (int k = 0; k < 120; ++k) {
                const double phi = 2.0 * M_PI * (k + 0.25) / 120.0;
                const glm::dvec3 radial(std::cos(phi), 0.0, std::sin(phi));
                edges.add(mapPoint(m, radial + glm::dvec3(0, y, 0)),
                          {mapNormal(m, radial), mapNormal(m, {0, y, 0})}, 0.5);
            }
        }
        parts.push_back(edgeCase(context, options, "cylinder",
                                 solidScene({{{makeShape(VKRT_SHAPE_CYLINDER, 0, m)}, kAlone}}), edges));
    }
    {
        EdgeRays edges{{}, {}, 33};
        for (int k = 0; k < 120; ++k) {
            const double phi = 2.0 * M_PI * (k + 0.25) / 120.0;
            const glm::dvec3 radial(std::cos(phi), 0.0, std::sin(phi));
            edges.add(mapPoint(m, radial + glm::dvec3(0, -1, 0)),
                      {mapNormal(m, radial + glm::dvec3(0, 0.5, 0)), mapNormal(m, {0, -1, 0})}, 0.5);
        }
        // The apex: every side normal (cos phi, 0.5, sin phi) at once, through eight of them.
        std::vector<glm::dvec3> apexNormals;
        for (int k = 0; k < 8; ++k) {
            const double phi = 2.0 * M_PI * k / 8.0;
            apexNormals.push_back(mapNormal(m, {std::cos(phi), 0.5, std::sin(phi)}));
        }
        for (int k = 0; k < 120; ++k) edges.add(mapPoint(m, {0, 1, 0}), apexNormals, 0.5);
        parts.push_back(edgeCase(context, options, "cone",
                                 solidScene({{{makeShape(VKRT_SHAPE_CONE, 0, m)}, kAlone}}), edges));
    }
    return combined("shapes: edges", "box edges and corners, cylinder rims, cone rim and apex, +-1 ulp",
                    parts);
}

// The edges where CSG operands meet: the rims of a box's bowls (a box minus a larger sphere), a lens's rim
// (two spheres' intersection) and the mouths of a bore (a sphere minus a cylinder).
StabilityResult csgEdges(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    std::vector<StabilityResult> parts;
    {
        // Box [-1, 1]^3 minus the sphere of radius 1.25 around its centre: on each face a circle of radius
        // 0.75.
        EdgeRays edges{{}, {}, 34};
        const double rho = std::sqrt(1.25 * 1.25 - 1.0);
        for (uint32_t face = 0; face < 6; ++face) {
            const int a = static_cast<int>(face / 2);
            glm::dvec3 n(0.0);
            n[a] = face % 2 ? 1.0 : -1.0;
            for (int k = 0; k < 48; ++k) {
                const double phi = 2.0 * M_PI * (k + 0.25) / 48.0;
                glm::dvec3 p = n;
                p[(a + 1) % 3] = rho * std::cos(phi);
                p[(a + 2) % 3] = rho * std::sin(phi);
                edges.add(mapPoint(m, p), {mapNormal(m, n), mapNormal(m, -p)}, 0.05);
            }
        }
        const Scene scene =
            solidScene({{{makeShape(VKRT_SHAPE_BOX, 0, m),
                          makeShape(VKRT_SHAPE_SPHERE, 0, m * glm::scale(glm::dmat4(1.0), glm::dvec3(1.25)))},
                         truthTable(2, [](uint32_t s) { return in(s, 0) && !in(s, 1); })}});
        parts.push_back(edgeCase(context, options, "box minus sphere", scene, edges));
    }
    {
        // Spheres of radius 1.5 around (0, 0, -+0.8): the lens's rim is the circle of radius 1.269 at z = 0.
        EdgeRays edges{{}, {}, 35};
        const double rho = std::sqrt(1.5 * 1.5 - 0.8 * 0.8);
        for (int k = 0; k < 240; ++k) {
            const double phi = 2.0 * M_PI * (k + 0.25) / 240.0;
            const glm::dvec3 p(rho * std::cos(phi), rho * std::sin(phi), 0.0);
            edges.add(mapPoint(m, p),
                      {mapNormal(m, p - glm::dvec3(0, 0, -0.8)), mapNormal(m, p - glm::dvec3(0, 0, 0.8))},
                      0.05);
        }
        auto sphere = [&](double z) {
            return makeShape(VKRT_SHAPE_SPHERE, 0,
                             m * glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, z)) *
                                 glm::scale(glm::dmat4(1.0), glm::dvec3(1.5)));
        };
        const Scene scene = solidScene(
            {{{sphere(-0.8), sphere(0.8)}, truthTable(2, [](uint32_t s) { return in(s, 0) && in(s, 1); })}});
        parts.push_back(edgeCase(context, options, "lens", scene, edges));
    }
    {
        // The unit sphere minus a cylinder of radius 0.4 along y: mouths at y = +-0.917.
        EdgeRays edges{{}, {}, 36};
        const double rho = 0.4, height = std::sqrt(1.0 - rho * rho);
        for (const double y : {-height, height}) {
            for (int k = 0; k < 120; ++k) {
                const double phi = 2.0 * M_PI * (k + 0.25) / 120.0;
                const glm::dvec3 p(rho * std::cos(phi), y, rho * std::sin(phi));
                edges.add(mapPoint(m, p), {mapNormal(m, p), mapNormal(m, {-p.x, 0.0, -p.z})}, 0.05);
            }
        }
        const Scene scene = solidScene(
            {{{makeShape(VKRT_SHAPE_SPHERE, 0, m),
               makeShape(VKRT_SHAPE_CYLINDER, 0, m * glm::scale(glm::dmat4(1.0), glm::dvec3(rho, 1.5, rho)))},
              truthTable(2, [](uint32_t s) { return in(s, 0) && !in(s, 1); })}});
        parts.push_back(edgeCase(context, options, "drilled sphere", scene, edges));
    }
    return combined("shapes: edges", "CSG rims: box minus sphere, lens, drilled sphere, +-1 ulp", parts);
}

// Rays of three kinds at a box-shaped region [-1, 1]^3 placed by `m`: from outside through points of the
// plane x = 0 (object space), from inside (origins within the box) through other points of it, and rays lying
// in that plane, aimed at points of it from outside.
std::vector<gpu::GpuRay> raysAcrossMidplane(const glm::dmat4& m, uint32_t stream, int count) {
    std::vector<gpu::GpuRay> rays;
    for (int k = 0; k < count; ++k) {
        const uint32_t i = static_cast<uint32_t>(k);
        auto r = [&](uint32_t d) { return 2.0 * random01(stream, i, d) - 1.0; };
        const glm::dvec3 onPlane(0.0, 0.95 * r(0), 0.95 * r(1));
        glm::dvec3 origin;
        switch (k % 3) {
            case 0:  // from outside
                origin = 3.0 * glm::normalize(glm::dvec3(r(2), r(3), r(4)) + glm::dvec3(1e-3));
                break;
            case 1:  // from inside
                origin = 0.95 * glm::dvec3(r(2), r(3), r(4));
                break;
            default:  // in the plane, from outside
                origin = glm::dvec3(0.0, 0.0, 0.0) +
                         3.0 * glm::normalize(glm::dvec3(0.0, r(2), r(3)) + glm::dvec3(0, 1e-3, 0));
                break;
        }
        rays.push_back(rayThrough(mapPoint(m, origin), mapPoint(m, onPlane)));
    }
    return rays;
}

// Operands with coincident faces, against the same solid without them. The union of two boxes that share a
// face (the halves x < 0 and x > 0 of [-1, 1]^3) traces as the one box: the same hits, never on the shared
// face, from outside, from inside, and along the shared face's plane.
StabilityResult coincidentUnion(const VulkanContext& context, const StabilityOptions& options) {
    const glm::dmat4 m = shapeFrame();
    auto half = [&](double x) {
        return makeShape(VKRT_SHAPE_BOX, 0,
                         m * glm::translate(glm::dmat4(1.0), glm::dvec3(x, 0, 0)) *
                             glm::scale(glm::dmat4(1.0), glm::dvec3(0.5, 1.0, 1.0)));
    };
    const Scene unionScene = solidScene(
        {{{half(-0.5), half(0.5)}, truthTable(2, [](uint32_t s) { return in(s, 0) || in(s, 1); })}});
    const Scene single = solidScene({{{makeShape(VKRT_SHAPE_BOX, 0, m)}, kAlone}});
    const std::vector<gpu::GpuRay> rays = raysAcrossMidplane(m, 41, 6000);
    const Answers reference = traceBoth(context, options, single, rays);
    std::vector<Expected> expected;
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        Expected e = expectedFrom(reference.cpu[i], hitCosine(single, reference.cpu[i], ray), false);
        // The shared face: the +x face (1) of the first half, the -x face (0) of the second, either side.
        e.forbidden = {{0u, 2u}, {0u, 3u}, {1u, 0u}, {1u, 1u}};
        expected.push_back(e);
    }
    return judgeRays("shapes: coincident faces", "union of two boxes sharing a face, against one box",
                     unionScene, rays, traceBoth(context, options, unionScene, rays), expected, 2.0);
}

// Rays perpendicular to face `face` of [-1, 1]^3 placed by `m`, from outside, over an n x n grid of cell
// centres covering the face.
void addFaceGrid(std::vector<gpu::GpuRay>& rays, const glm::dmat4& m, uint32_t face, int n) {
    const int a = static_cast<int>(face / 2);
    glm::dvec3 normal(0.0);
    normal[a] = face % 2 ? 1.0 : -1.0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            glm::dvec3 p = normal;
            p[(a + 1) % 3] = -1.0 + 2.0 * (i + 0.5) / n;
            p[(a + 2) % 3] = -1.0 + 2.0 * (j + 0.5) / n;
            rays.push_back(rayThrough(mapPoint(m, p + 3.0 * normal), mapPoint(m, p)));
        }
    }
}

// A box minus a box whose faces lie flush with some of its own, against the same difference with the
// subtracted box sticking out beyond them: the same hit, on the same face, for every ray of a grid
// perpendicular to the flush faces (no speckles where the coincident faces tie).
StabilityResult flushDifference(const VulkanContext& context, const StabilityOptions& options, bool pocket) {
    const glm::dmat4 m = shapeFrame();
    auto box = [&](glm::dvec3 center, glm::dvec3 half) {
        return makeShape(VKRT_SHAPE_BOX, 0,
                         m * glm::translate(glm::dmat4(1.0), center) * glm::scale(glm::dmat4(1.0), half));
    };
    const std::array<uint32_t, 8> minus = truthTable(2, [](uint32_t s) { return in(s, 0) && !in(s, 1); });
    std::vector<gpu::GpuRay> rays;
    Scene flush, reference;
    if (pocket) {
        // A pocket [-0.5, 0.5] x [0, 1] x [-0.5, 0.5]: its mouth flush with the top face.
        flush = solidScene({{{box({0, 0, 0}, {1, 1, 1}), box({0, 0.5, 0}, {0.5, 0.5, 0.5})}, minus}});
        reference = solidScene({{{box({0, 0, 0}, {1, 1, 1}), box({0, 0.75, 0}, {0.5, 0.75, 0.5})}, minus}});
        addFaceGrid(rays, m, 3, 64);
    } else {
        // The upper half cut off by a box [-1, 1] x [0, 2] x [-1, 1]: four side faces flush over y > 0.
        flush = solidScene({{{box({0, 0, 0}, {1, 1, 1}), box({0, 1, 0}, {1, 1, 1})}, minus}});
        reference = solidScene({{{box({0, 0, 0}, {1, 1, 1}), box({0, 1, 0}, {1.5, 1, 1.5})}, minus}});
        for (const uint32_t face : {0u, 1u, 4u, 5u}) addFaceGrid(rays, m, face, 32);
        addFaceGrid(rays, m, 3, 32);
    }
    const Answers expectedAnswers = traceBoth(context, options, reference, rays);
    std::vector<Expected> expected;
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        expected.push_back(
            expectedFrom(expectedAnswers.cpu[i], hitCosine(reference, expectedAnswers.cpu[i], ray), true));
    }
    return judgeRays("shapes: coincident faces",
                     pocket ? "box minus a pocket flush with its top, grid of rays onto it"
                            : "box minus a box flush with four sides, grids of rays onto them",
                     flush, rays, traceBoth(context, options, flush, rays), expected, 2.0);
}

// Solids at scale 1e-4 and 1e4 (every map and ray scaled, about the origin) against the unit scale, on each
// device: the same hits on the same faces at the scaled distances. Then scenes/csg.gltf rendered at both
// scales, against its unit-scale image.
std::vector<gpu::GpuRay> randomRays(const Aabb& bounds, uint32_t stream, int count) {
    std::vector<gpu::GpuRay> rays;
    const glm::vec3 lo = bounds.min, extent = bounds.extent(), center = bounds.center();
    const float radius = glm::length(extent);
    for (int k = 0; k < count; ++k) {
        const uint32_t i = static_cast<uint32_t>(k);
        auto r = [&](uint32_t d) { return vkrtRandom(stream, i, 0, d); };
        const glm::vec3 inside = lo + extent * glm::vec3(r(0), r(1), r(2));
        glm::vec3 origin;
        switch (k % 3) {
            case 0:  // from a fixed eye
                origin = center + glm::vec3(0.3f, 0.2f, 1.5f) * radius;
                break;
            case 1:  // from another point inside the bounds
                origin = lo + extent * glm::vec3(r(3), r(4), r(5));
                break;
            default:
                origin = center + radius * (glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f);
                break;
        }
        rays.push_back({origin, 0.0f, glm::normalize(inside - origin), 1e30f});
    }
    return rays;
}

Scene scaledSolids(double scale) {
    const glm::dmat4 s = glm::scale(glm::dmat4(1.0), glm::dvec3(scale));
    const glm::dmat4 m = shapeFrame();
    auto at = [&](glm::dvec3 t, glm::dvec3 half) {
        return s * glm::translate(glm::dmat4(1.0), t) * m * glm::scale(glm::dmat4(1.0), half);
    };
    const std::array<uint32_t, 8> minus = truthTable(2, [](uint32_t b) { return in(b, 0) && !in(b, 1); });
    return solidScene({
        {{makeShape(VKRT_SHAPE_BOX, 0, at({-2.0, 0.0, 0.0}, {0.7, 0.7, 0.7})),
          makeShape(VKRT_SHAPE_SPHERE, 0, at({-2.0, 0.0, 0.0}, {0.9, 0.9, 0.9}))},
         minus},
        {{makeShape(VKRT_SHAPE_SPHERE, 0, at({0.0, 0.0, -0.5}, {1.0, 1.0, 1.0})),
          makeShape(VKRT_SHAPE_SPHERE, 0, at({0.0, 0.0, 0.5}, {1.0, 1.0, 1.0}))},
         truthTable(2, [](uint32_t b) { return in(b, 0) && in(b, 1); })},
        {{makeShape(VKRT_SHAPE_SPHERE, 0, at({2.0, 0.0, 0.0}, {0.8, 0.8, 0.8})),
          makeShape(VKRT_SHAPE_CYLINDER, 0, at({2.0, 0.0, 0.0}, {0.3, 1.2, 0.3}))},
         minus},
        {{makeShape(VKRT_SHAPE_CYLINDER, 0, at({-1.0, 1.8, 0.0}, {0.5, 0.6, 0.4}))}, kAlone},
        {{makeShape(VKRT_SHAPE_CONE, 0, at({1.0, 1.8, 0.0}, {0.5, 0.6, 0.4}))}, kAlone},
    });
}

std::vector<StabilityResult> shapeScales(const VulkanContext& context, const StabilityOptions& options) {
    std::vector<StabilityResult> results;
    const Scene unit = scaledSolids(1.0);
    const std::vector<gpu::GpuRay> unitRays = randomRays(unit.bounds, 51, 30000);
    const Answers unitAnswers = traceBoth(context, options, unit, unitRays);
    const double unitSize = glm::length(unit.bounds.extent());
    for (const double scale : {1e-4, 1e4}) {
        const Scene scene = scaledSolids(scale);
        std::vector<gpu::GpuRay> rays = unitRays;
        for (gpu::GpuRay& r : rays) {
            r.origin = glm::vec3(glm::dvec3(r.origin) * scale);
            r.tMax = 1e30f;
        }
        const Answers answers = traceBoth(context, options, scene, rays);
        // Each device against its own unit-scale answers; grazing hits (|cos| < 0.05) are left out, where the
        // float surfaces of the two scales may part.
        StabilityResult result;
        result.group = "shapes: scale";
        std::ostringstream name;
        name << "solids x" << scale << ": 30,000 rays against x1";
        result.name = name.str();
        uint64_t leaks = 0, wrong = 0;
        Tally tally;
        for (size_t i = 0; i < rays.size(); ++i) {
            const RayT<double> unitRay{glm::dvec3(unitRays[i].origin), glm::dvec3(unitRays[i].direction)};
            for (const bool onGpu : {true, false}) {
                const RayAnswer& before = onGpu ? unitAnswers.gpu[i] : unitAnswers.cpu[i];
                const RayAnswer& after = onGpu ? answers.gpu[i] : answers.cpu[i];
                const double cosine = hitCosine(unit, before, unitRay);
                if (cosine < 0.05) continue;
                std::string problem;
                if (before.hit && !after.hit) {
                    ++leaks;
                    problem = "leaks";
                } else if (!before.hit && after.hit) {
                    ++wrong;
                    problem = "hits where nothing was";
                } else if (before.hit && (before.shape != after.shape || before.face != after.face ||
                                          std::abs(after.t / scale - before.t) * cosine >
                                              1e-5 * before.t + 1e-6 * unitSize)) {
                    ++wrong;
                    problem = "hits elsewhere";
                }
                if (problem.empty()) continue;
                tally.add(
                    std::string(onGpu ? "GPU " : "CPU ") + problem + shapeOf(scene, after, before), [&] {
                        std::ostringstream s;
                        s << (onGpu ? "GPU" : "CPU") << " ray " << i << " " << problem << ": "
                          << describe(after) << " (the distance / scale: " << std::setprecision(9)
                          << after.t / scale << "), at x1 " << describe(before) << "; " << describe(rays[i]);
                        return s.str();
                    });
            }
        }
        result.note = tally.note();
        result.leaks = leaks;
        result.wrongHits = wrong;
        results.push_back(result);
    }
    // scenes/csg.gltf under a root scaled by 1e-4 and 1e4: the image must not change.
    RenderRequest request;
    request.settings = settingsFor(options);
    request.height = options.height;
    const std::filesystem::path path = options.sourceDir / "scenes" / "csg.gltf";
    const Scene unitScene = transformedVariant(path, 1.0, 0.0, options.workDir, "csg-unit");
    const RenderSetup unitSetup = resolveRender(request, unitScene);
    const Rendered reference = renderBoth(context, unitScene, unitSetup.camera, unitSetup.settings, options);
    results.push_back(measure(options, "shapes: scale", "csg x1", reference));
    for (const double scale : {1e-4, 1e4}) {
        std::ostringstream name;
        name << "csg x" << scale;
        const Scene scene = transformedVariant(path, scale, 0.0, options.workDir, name.str());
        const RenderSetup setup = resolveRender(request, scene);
        const Rendered r = renderBoth(context, scene, setup.camera, setup.settings, options);
        StabilityResult result = measure(options, "shapes: scale", name.str(), r);
        setInvariance(result, r.gpu, reference.gpu);
        results.push_back(result);
    }
    return results;
}

std::string format(std::optional<double> value, int digits = 4) {
    if (!value) return "";
    std::ostringstream s;
    s << std::setprecision(digits) << *value;
    return s.str();
}

}  // namespace

std::vector<StabilityResult> runStabilitySuite(const VulkanContext& context,
                                               const StabilityOptions& options) {
    std::filesystem::create_directories(options.workDir);
    std::vector<StabilityResult> results;
    if (options.cases == StabilityCases::ShapesOnly) return runShapeStabilityCases(context, options);
    invarianceCases(context, options, results);
    results.push_back(grazingPlane(context, options));
    results.push_back(lightAboveSurface(context, options));
    results.push_back(terminator(context, options));
    results.push_back(thinSlab(context, options));
    results.push_back(coincidentFaces(context, options));
    results.push_back(nearlyCoincidentFaces(context, options));
    for (SphereKind kind : {SphereKind::Mesh, SphereKind::Analytic}) {
        results.push_back(
            sphereCase(context, options, glass(2.4f), "total internal reflection, ior 2.4 sphere", kind));
        results.push_back(
            sphereCase(context, options, glass(1.0f), "ior 1.0 sphere (must be invisible)", kind, true));
        results.push_back(
            nestedDielectrics(context, options, 1.5f, "nested dielectrics: glass sphere in water", kind));
        results.push_back(
            nestedDielectrics(context, options, 1.33f, "index-matched sphere in water (must vanish)", kind));
    }
    results.push_back(distantSphere(context, options));
    results.push_back(hugeGroundSphere(context, options));
    results.push_back(hugeGroundQuad(context, options));
    results.push_back(degenerateGeometry(context, options));
    results.push_back(watertightness(context, options, false));
    results.push_back(watertightness(context, options, true));
    results.push_back(extremeEmission(context, options));
    results.push_back(blackMaterials(context, options));
    results.push_back(roughnessExtremes(context, options, 0.0f));
    results.push_back(roughnessExtremes(context, options, 1.0f));
    results.push_back(longAccumulation(context, options));
    if (options.cases == StabilityCases::All) {
        for (StabilityResult& r : runShapeStabilityCases(context, options)) results.push_back(std::move(r));
    }
    return results;
}

std::vector<StabilityResult> runShapeStabilityCases(const VulkanContext& context,
                                                    const StabilityOptions& options) {
    std::filesystem::create_directories(options.workDir);
    std::vector<StabilityResult> results;
    results.push_back(grazingBox(context, options));
    results.push_back(grazingCylinder(context, options));
    results.push_back(grazingCone(context, options));
    results.push_back(shapeEdges(context, options));
    results.push_back(csgEdges(context, options));
    results.push_back(coincidentUnion(context, options));
    results.push_back(flushDifference(context, options, true));
    results.push_back(flushDifference(context, options, false));
    for (const StabilityResult& r : shapeScales(context, options)) results.push_back(r);
    return results;
}

std::string stabilityTable(const std::vector<StabilityResult>& results) {
    std::ostringstream t;
    t << "| group | case | non-finite | GPU vs CPU: pixels off | mean rel. error | invariance: pixels off | "
         "mean rel. "
         "error | leaks | wrong hits | acne | accumulation error |\n";
    t << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const StabilityResult& r : results) {
        const bool rendered = !r.leaks && !r.accumulationError;
        t << "| " << r.group << " | " << r.name << " | " << r.nonFiniteSamples << " | "
          << (rendered ? format(r.gpuVsCpuOff) : "") << " | "
          << (rendered ? format(r.gpuVsCpuMeanRelative) : "") << " | " << format(r.invarianceOff) << " | "
          << format(r.invarianceMeanRelative) << " | " << (r.leaks ? std::to_string(*r.leaks) : "") << " | "
          << (r.wrongHits ? std::to_string(*r.wrongHits) : "") << " | " << format(r.acne) << " | "
          << format(r.accumulationError, 3) << " |\n";
    }
    return t.str();
}

}  // namespace vkrt
