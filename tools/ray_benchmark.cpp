// Ray-throughput benchmark: traces the same camera, shadow and diffuse-bounce rays through vkrt's GPU
// traversal (shaders/raycast.comp) several times and prints JSON with median, minimum and maximum Mrays/s
// per ray kind, the BVH build time and SAH cost, and the device.
//
//   ray_benchmark [--scene FILE | --triangles N] [--width W --height H] [--runs R] [--device-index N]
//                 [--repeat-ms MS] [--device-buffers mapped|staged] [--count-iterations]
//                 [--variant DEFINE[,DEFINE...]]...
//   (--help lists every option with its range; a bad argument prints one line and exits 2)
//
// Without --scene the input is a UV sphere of about N triangles (default 1M) over a ground quad.
// Camera rays go through every pixel of the scene's camera; shadow rays run from each camera hit to a
// point above the scene (any hit); diffuse rays leave each camera hit in a cosine-distributed direction
// (closest hit). On a GPU each timed call traces its batch repeatedly for about --repeat-ms (50), back to
// back, and reports the time per trace ("repeats" in the JSON): a single trace takes about a millisecond.
// Each kernel traces each batch once, untimed, before its timed runs (lavapipe compiles at the first
// dispatch).
// --count-iterations adds, per ray kind, the traversal's loop iterations per ray (what llvmpipe counts
// against its budget of 65535 per invocation), from a kernel built to count them.
// --variant compiles the kernel again with extra defines and traces the same rays with it, run for run
// alternately with the default kernel, and reports its rates, their ratio to the default's (per CPU second,
// and per GPU second where the device has timestamps) and the share of rays whose hit is the default's bit
// for bit (A/B tests of shader changes that a busy machine's noise would hide between processes). A variant
// with VKRT_BOUND_GEOMETRY, VKRT_TEXEL_SCENE or VKRT_ADDRESSED_SCENE reads the scene that way
// (gpu_raycaster.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <sys/resource.h>

#include <nlohmann/json.hpp>

#include "app/render_policy.h"
#include "bvh/triangle_bvh.h"
#include "command_line.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/shader_compiler.h"
#include "gpu/vulkan_context.h"
#include "random.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "scene/shading_inputs.h"
#ifdef VKRT_HAVE_EMBREE
#include "embree_tracer.h"
#endif

namespace vkrt {
namespace {

struct Statistics {
    double median, min, max;
};

Statistics summarize(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
    return {median, values.front(), values.back()};
}

// CPU seconds used by every thread of this process so far (Embree's workers included).
double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

Scene sphereOverGround(size_t triangleTarget) {
    Scene scene;
    Material white;
    white.metallic = 0.0f;
    scene.materials.push_back(white);
    const int segments = std::max(4, static_cast<int>(std::sqrt(static_cast<double>(triangleTarget))));
    for (const Triangle& t : makeUvSphere(glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, segments / 2, segments)) {
        if (glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)) > 0.0f)
            addFlatTriangle(scene, t.v0, t.v1, t.v2, 0);
    }
    addFlatQuad(scene, {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, 0);
    finalizeScene(scene);
    Camera camera;
    camera.name = "benchmark";
    camera.position = {0.0, 1.5, 4.0};
    camera.forward = glm::normalize(glm::dvec3(0.0, -0.35, -1.0));
    camera.right = glm::dvec3(1.0, 0.0, 0.0);
    camera.up = glm::cross(camera.right, camera.forward);
    camera.yfov = 0.8;
    scene.cameras.push_back(camera);
    return scene;
}

// The pinhole ray through a pixel's centre (shaders/camera.h, as both renderers make it).
gpu::GpuRay cameraRay(const Camera& camera, int x, int y, int width, int height) {
    const shading::CameraRay ray =
        shading::cameraRay(cameraFrame(camera, Aabb{}, width, height), x + 0.5, y + 0.5, 0.5, 0.5);
    return {glm::vec3(ray.origin), 0.0f, glm::vec3(ray.direction), 1e30f};
}

}  // namespace
}  // namespace vkrt

int main(int argc, char** argv) {
    using namespace vkrt;
    std::string scenePath;
    size_t triangles = 1'000'000;
    int width = 1024, height = 1024, runs = 5, deviceIndex = -1;
    bool countIterations = false;
    double repeatMs = -1.0;  // -1: by the device
    std::string deviceBuffers = "mapped";
    std::vector<std::string> variants;
    CLI::App app{"Traces camera, shadow and diffuse rays through the GPU traversal and prints JSON.",
                 "ray_benchmark"};
    auto* sceneOption =
        app.add_option("--scene", scenePath, "a glTF file instead of the sphere")->check(CLI::ExistingFile);
    app.add_option("--triangles", triangles, "about this many triangles in the sphere over a ground quad")
        ->check(CLI::Range(size_t{1}, size_t{1'000'000'000}))
        ->excludes(sceneOption)
        ->capture_default_str();
    app.add_option("--width", width, "camera rays across")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--height", height, "camera rays down")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--runs", runs, "traces per ray kind")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--device-index", deviceIndex, "Vulkan device (-1: the best one)")
        ->check(CLI::Range(-1, 1023))
        ->capture_default_str();
    app.add_option(
           "--repeat-ms", repeatMs,
           "trace each batch repeatedly, back to back in one submission, for about this long, and report "
           "the time per trace [50 on a GPU, 0 (once) on a CPU device]")
        ->check(CLI::Range(0.0, 10000.0));
    app.add_option(
           "--device-buffers", deviceBuffers,
           "where the rays, hits and scene lie: mapped (device memory the host maps, where the device "
           "has such) or staged (device memory the host does not see, written and read through copies; "
           "mapped where the device has none, as lavapipe)")
        ->check(CLI::IsMember({"mapped", "staged"}))
        ->capture_default_str();
    app.add_flag("--count-iterations", countIterations,
                 "also report the traversal's loop iterations per ray (mean, median, 99th percentile, maximum)");
    app.add_option("--variant", variants,
                   "also trace with the kernel compiled with these comma-separated defines, alternately");
    if (const std::optional<int> exitCode = parseCommandLine(app, argc, argv)) return *exitCode;
    try {
        const Scene scene = scenePath.empty() ? sphereOverGround(triangles) : loadGltf(scenePath);
        RenderRequest request;
        request.settings.width = width;
        request.height = height;
        const Camera camera = resolveRender(request, scene).camera;

        const TriangleBvh triangleBvh = buildTriangleBvh(scene.triangles);
        const FlatBvh& flat = triangleBvh.flat;
        const BvhStats& stats = triangleBvh.stats;

        ContextOptions options;
        options.deviceIndex = deviceIndex;
        options.deviceBuffers = deviceBuffers == "staged" ? DeviceBuffers::Staged : DeviceBuffers::Mapped;
        const VulkanContext context(options);
        GpuRaycaster raycaster(context, scene, flat, defaultShaderCacheDir());
        std::vector<std::unique_ptr<GpuRaycaster>> variantTracers;
        for (const std::string& variant : variants) {
            std::vector<std::string> defines;
            for (size_t start = 0; start <= variant.size();) {
                const size_t end = std::min(variant.find(',', start), variant.size());
                if (end > start) defines.push_back(variant.substr(start, end - start));
                start = end + 1;
            }
            variantTracers.push_back(
                std::make_unique<GpuRaycaster>(context, scene, flat, defaultShaderCacheDir(), defines));
        }
        std::unique_ptr<GpuRaycaster> counter;
        if (countIterations) {
            counter = std::make_unique<GpuRaycaster>(context, scene, flat, defaultShaderCacheDir(),
                                                     std::vector<std::string>{"VKRT_COUNT_ITERATIONS"});
        }

        // Camera rays, then shadow and diffuse rays from their hits.
        std::vector<gpu::GpuRay> cameraRays;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) cameraRays.push_back(cameraRay(camera, x, y, width, height));
        const std::vector<gpu::GpuHit> primary = raycaster.trace(cameraRays, RaycastMode::Closest);
        const glm::vec3 lightPoint = scene.bounds.center() + glm::vec3(0.0f, scene.bounds.extent().y, 0.0f) +
                                     0.3f * scene.bounds.extent();
        std::vector<gpu::GpuRay> shadowRays, diffuseRays;
        for (size_t i = 0; i < primary.size(); ++i) {
            if (primary[i].primitive == VKRT_NO_HIT) continue;
            const Triangle& t = scene.triangles[primary[i].primitive];
            glm::vec3 n = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
            if (glm::dot(n, cameraRays[i].direction) > 0.0f) n = -n;
            const glm::vec3 p = cameraRays[i].origin + primary[i].t * cameraRays[i].direction;
            const float epsilon = 1e-4f * glm::length(scene.bounds.extent());
            const glm::vec3 origin = p + epsilon * n;
            const glm::vec3 toLight = lightPoint - origin;
            shadowRays.push_back({origin, 0.0f, glm::normalize(toLight), glm::length(toLight)});
            // Cosine-weighted direction about n (Malley's method).
            const float u = vkrtRandom(1, static_cast<uint32_t>(i), 0, 0),
                        v = vkrtRandom(1, static_cast<uint32_t>(i), 0, 1);
            const float r = std::sqrt(u), phi = 6.2831853f * v;
            const glm::vec3 a = std::abs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
            const glm::vec3 b1 = glm::normalize(glm::cross(a, n)), b2 = glm::cross(n, b1);
            const glm::vec3 d =
                r * std::cos(phi) * b1 + r * std::sin(phi) * b2 + std::sqrt(std::max(0.0f, 1.0f - u)) * n;
            diffuseRays.push_back({origin, 0.0f, glm::normalize(d), 1e30f});
        }

#ifdef VKRT_HAVE_EMBREE
        const EmbreeTracer embree(scene.triangles);
        const int embreeThreads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
#endif
        nlohmann::json kinds;
        // A GPU traces a million rays in about a millisecond, too short a time to measure alone (single
        // traces on an H200 spread by up to 12% within a run). So each timed call traces the batch as often
        // as fills about --repeat-ms, back to back, after one such call untimed; a CPU device (lavapipe)
        // takes 100 ms or more a batch and traces it once.
        const bool cpuDevice = context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        if (repeatMs < 0.0) repeatMs = cpuDevice ? 0.0 : 50.0;
        auto repeatsFor = [&](double msPerTrace) {
            if (repeatMs <= 0.0 || !(msPerTrace > 0.0)) return 1u;
            return static_cast<uint32_t>(std::clamp(std::ceil(repeatMs / msPerTrace), 1.0, 10000.0));
        };
        auto measure = [&](const char* kind, const std::vector<gpu::GpuRay>& rays, RaycastMode mode) {
            // No rays of this kind (no camera ray hit anything): nothing to time.
            if (rays.empty()) {
                kinds[kind] = {{"rays", 0}};
                return;
            }
            // Every kernel traces the batch once untimed first: lavapipe compiles a kernel at its first
            // dispatch (a GPU's driver when its pipeline is made, before the timing starts).
            RaycastTiming probe;
            raycaster.trace(rays, mode, &probe);
            for (const auto& tracer : variantTracers) tracer->trace(rays, mode);
            uint32_t repeats = 1;
            if (repeatMs > 0.0) {
                const auto ms = [](const RaycastTiming& t) { return t.gpuMs > 0.0 ? t.gpuMs : t.wallMs; };
                raycaster.trace(rays, mode, &probe, repeatsFor(ms(probe)));  // the warm-up at the repeats
                repeats = repeatsFor(ms(probe));
            }
            std::vector<double> gpuRates, wallRates, cpuRates;
            std::vector<std::vector<double>> variantCpuRates(variants.size()),
                variantWallRates(variants.size()), variantGpuRates(variants.size());
#ifdef VKRT_HAVE_EMBREE
            std::vector<double> embreeRates, embreeCpuRates;
            std::vector<uint32_t> embreeHits;
#endif
            // The runs interleaved: each traces with every variant, the default kernel and Embree in turn, so
            // that the machine's drift hits them alike and the ratios of medians are from one run.
            for (int run = 0; run < runs; ++run) {
                for (size_t v = 0; v < variants.size(); ++v) {
                    RaycastTiming timing;
                    variantTracers[v]->trace(rays, mode, &timing, repeats);
                    variantCpuRates[v].push_back(rays.size() / timing.cpuMs / 1e3);
                    variantWallRates[v].push_back(rays.size() / timing.wallMs / 1e3);
                    if (timing.gpuMs > 0.0) variantGpuRates[v].push_back(rays.size() / timing.gpuMs / 1e3);
                }
                RaycastTiming timing;
                raycaster.trace(rays, mode, &timing, repeats);
                cpuRates.push_back(rays.size() / timing.cpuMs / 1e3);
                if (timing.gpuMs > 0.0) gpuRates.push_back(rays.size() / timing.gpuMs / 1e3);
                wallRates.push_back(rays.size() / timing.wallMs / 1e3);
#ifdef VKRT_HAVE_EMBREE
                const double cpuStart = processCpuSeconds();
                const double ms = embree.trace(rays, mode == RaycastMode::Any, embreeThreads, embreeHits);
                embreeCpuRates.push_back(rays.size() / (processCpuSeconds() - cpuStart) / 1e6);
                embreeRates.push_back(rays.size() / ms / 1e3);
#endif
            }
            const Statistics wall = summarize(wallRates);
            nlohmann::json entry = {
                {"rays", rays.size()},
                {"repeats", repeats},
                {"mrays_per_s", {{"median", wall.median}, {"min", wall.min}, {"max", wall.max}}},
                {"mrays_per_cpu_s", summarize(cpuRates).median}};
            if (!gpuRates.empty()) {
                const Statistics g = summarize(gpuRates);
                entry["mrays_per_gpu_s"] = {{"median", g.median}, {"min", g.min}, {"max", g.max}};
            }
#ifdef VKRT_HAVE_EMBREE
            // The same rays through Embree, traced in the same runs; the ratio of same-run medians.
            const Statistics e = summarize(embreeRates);
            entry["embree_mrays_per_s"] = {{"median", e.median}, {"min", e.min}, {"max", e.max}};
            entry["vkrt_over_embree"] = wall.median / e.median;
            // Per CPU second (both use every hardware thread): the same ratio, less sensitive to a busy machine.
            entry["embree_mrays_per_cpu_s"] = summarize(embreeCpuRates).median;
            entry["vkrt_over_embree_cpu"] = summarize(cpuRates).median / summarize(embreeCpuRates).median;
            // Agreement on which rays hit, as a check that both traced the same thing.
            const std::vector<gpu::GpuHit> vkrtHits = raycaster.trace(rays, mode);
            size_t agree = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                agree += (vkrtHits[i].primitive != VKRT_NO_HIT) == (embreeHits[i] != VKRT_NO_HIT);
            }
            entry["hit_agreement"] = static_cast<double>(agree) / static_cast<double>(rays.size());
#endif
            const std::vector<gpu::GpuHit> defaultHits =
                variants.empty() ? std::vector<gpu::GpuHit>{} : raycaster.trace(rays, mode);
            for (size_t v = 0; v < variants.size(); ++v) {
                // Run for run against the default kernel: the median of the per-run ratios, per CPU second (a
                // CPU device's work) and, where the device has timestamps, per GPU second (a GPU's).
                std::vector<double> ratios, gpuRatios;
                for (int run = 0; run < runs; ++run)
                    ratios.push_back(variantCpuRates[v][run] / cpuRates[run]);
                nlohmann::json& variant = entry["variants"][variants[v]];
                variant = {{"mrays_per_s", summarize(variantWallRates[v]).median},
                           {"mrays_per_cpu_s", summarize(variantCpuRates[v]).median},
                           {"over_default_cpu", summarize(ratios).median}};
                if (variantGpuRates[v].size() == gpuRates.size() && !gpuRates.empty()) {
                    for (size_t run = 0; run < gpuRates.size(); ++run) {
                        gpuRatios.push_back(variantGpuRates[v][run] / gpuRates[run]);
                    }
                    variant["mrays_per_gpu_s"] = summarize(variantGpuRates[v]).median;
                    variant["over_default_gpu"] = summarize(gpuRatios).median;
                }
                // The share of rays whose hit (primitive, distance, barycentrics) is the default kernel's,
                // bit for bit: a variant that changes what is found shows here, not as a speed-up.
                const std::vector<gpu::GpuHit> hits = variantTracers[v]->trace(rays, mode);
                size_t same = 0;
                for (size_t i = 0; i < rays.size(); ++i) {
                    same += std::memcmp(&hits[i], &defaultHits[i], sizeof(gpu::GpuHit)) == 0;
                }
                variant["same_hits"] = static_cast<double>(same) / static_cast<double>(rays.size());
            }
            if (counter) {
                std::vector<double> iterations;
                size_t incomplete = 0;
                for (const gpu::GpuHit& hit : counter->trace(rays, mode)) {
                    if (std::isnan(hit.t))
                        ++incomplete;  // a walk the driver cut short
                    else
                        iterations.push_back(hit.u);
                }
                std::sort(iterations.begin(), iterations.end());
                double sum = 0.0;
                for (double n : iterations) sum += n;
                const size_t n = iterations.size();
                // The 99th percentile by nearest rank: the smallest value at least 99% of the walks reach.
                const size_t p99 = n ? (n * 99 + 99) / 100 - 1 : 0;
                entry["loop_iterations"] = {{"mean", n ? sum / static_cast<double>(n) : 0.0},
                                            {"median", n ? summarize(iterations).median : 0.0},
                                            {"p99", n ? iterations[p99] : 0.0},
                                            {"max", n ? iterations.back() : 0.0},
                                            {"incomplete", incomplete}};
            }
            kinds[kind] = entry;
        };
        measure("camera", cameraRays, RaycastMode::Closest);
        measure("shadow", shadowRays, RaycastMode::Any);
        measure("diffuse", diffuseRays, RaycastMode::Closest);

        const nlohmann::json report = {
            {"benchmark", "rays"},
            {"input", scenePath.empty() ? "uv-sphere over ground" : scenePath},
            {"triangles", scene.triangles.size()},
            {"device", context.description().name},
            {"device_type", context.description().type},
            {"driver", context.description().driver},
            {"scene_access", sceneAccessName(raycaster.sceneAccess())},
            {"device_buffers", context.mapsDeviceBuffers() ? "mapped" : "staged"},
            {"host_threads", std::thread::hardware_concurrency()},
            {"runs", runs},
            {"bvh",
             {{"build_ms", stats.buildMs},
              {"nodes", stats.nodes},
              {"depth", stats.depth},
              {"sah_cost", stats.sahCost}}},
            {"kinds", kinds},
#ifdef VKRT_HAVE_EMBREE
            {"embree",
             {{"version", EmbreeTracer::version()},
              {"threads", embreeThreads},
              {"build_ms", embree.buildMs()}}},
#endif
        };
        std::printf("%s\n", report.dump(2).c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ray_benchmark: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
