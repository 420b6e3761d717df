#include "stability/stability_suite.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

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
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
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
// punctual intensities are multiplied by scale^2 so that irradiance stays the same.
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
    const std::filesystem::path file = workDir / (name + ".gltf");
    std::ofstream(file) << gltf.dump();
    return loadGltf(file.string());
}

Camera lookAt(glm::dvec3 eye, glm::dvec3 target, double yfov) {
    Camera camera;
    camera.name = "stability";
    camera.position = eye;
    camera.forward = glm::normalize(target - eye);
    camera.right = glm::normalize(glm::cross(camera.forward, glm::dvec3(0.0, 1.0, 0.0)));
    camera.up = glm::cross(camera.right, camera.forward);
    camera.yfov = yfov;
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
        for (double scale : {1e-5, 1e-3, 1e3, 1e6}) {
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

StabilityResult coincidentFaces(const VulkanContext& context, const StabilityOptions& options) {
    Scene scene = checkerboard();
    scene.materials.push_back(diffuse({0.1f, 0.3f, 0.9f}));
    addFlatQuad(scene, {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, 2);  // on top of the board
    finalizeScene(scene);
    const Rendered r = renderBoth(context, scene, lookAt({0.0, 3.0, 5.0}, {0.0, 0.0, 0.0}, 0.8),
                                  settingsFor(options), options);
    return measure(options, "thin media", "coincident faces", r);
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
    invarianceCases(context, options, results);
    results.push_back(grazingPlane(context, options));
    results.push_back(lightAboveSurface(context, options));
    results.push_back(terminator(context, options));
    results.push_back(thinSlab(context, options));
    results.push_back(coincidentFaces(context, options));
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
    results.push_back(degenerateGeometry(context, options));
    results.push_back(watertightness(context, options, false));
    results.push_back(watertightness(context, options, true));
    results.push_back(extremeEmission(context, options));
    results.push_back(blackMaterials(context, options));
    results.push_back(roughnessExtremes(context, options, 0.0f));
    results.push_back(roughnessExtremes(context, options, 1.0f));
    results.push_back(longAccumulation(context, options));
    return results;
}

std::string stabilityTable(const std::vector<StabilityResult>& results) {
    std::ostringstream t;
    t << "| group | case | non-finite | GPU vs CPU: pixels off | mean rel. error | invariance: pixels off | "
         "mean rel. "
         "error | leaks | acne | accumulation error |\n";
    t << "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const StabilityResult& r : results) {
        const bool rendered = !r.leaks && !r.accumulationError;
        t << "| " << r.group << " | " << r.name << " | " << r.nonFiniteSamples << " | "
          << (rendered ? format(r.gpuVsCpuOff) : "") << " | "
          << (rendered ? format(r.gpuVsCpuMeanRelative) : "") << " | " << format(r.invarianceOff) << " | "
          << format(r.invarianceMeanRelative) << " | " << (r.leaks ? std::to_string(*r.leaks) : "") << " | "
          << format(r.acne) << " | " << format(r.accumulationError, 3) << " |\n";
    }
    return t.str();
}

}  // namespace vkrt
