#include "app/prepared_render.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <future>
#include <memory>
#include <string>
#include <utility>

#include "app/gpu_run.h"
#include "app/host_memory.h"
#include "common/atomic_file.h"
#include "common/elapsed_time.h"
#include "image/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"
#include "scene/shading_inputs.h"

namespace vkrt {
namespace {

// The --environment map, decoded and checked; a file that cannot be used is bad input (exit code 2).
EnvironmentMap loadEnvironment(const Options& options) {
    Image image;
    try {
        image = readRadianceImage(options.environmentPath, hostMemoryFor(options).bytes);
    } catch (const ImageError& e) {
        throw UsageError(std::string("--environment: ") + e.what());
    } catch (const MemoryError& e) {
        throw MemoryError(std::string("--environment: ") + e.what());
    }
    try {
        return makeEnvironmentMap(options.environmentPath, image.width, image.height, std::move(image.pixels),
                                  options.environmentRotation, options.environmentStrength);
    } catch (const SceneError& e) {
        throw UsageError(std::string("--environment: ") + e.what());
    }
}

// Estimates the host memory the render will take and refuses it (MemoryError) when it does not fit;
// records the estimate and what was available.
void checkHostMemoryFor(const Options& options, bool measuresError, bool shared, const Scene& scene,
                        const RenderSettings& settings, const VulkanContext* context,
                        RunReport::Memory& memory) {
    HostMemoryInputs inputs;
    inputs.shared = shared;
    inputs.triangles = scene.triangles.size();
    inputs.textureBytes = packedTextureBytes(scene);
    if (scene.environment.present())
        inputs.environmentTexels = static_cast<uint64_t>(scene.environment.width) * scene.environment.height;
    inputs.width = settings.width;
    inputs.height = settings.height;
    inputs.gpu = context != nullptr;
    inputs.deviceInHostMemory = context && context->description().type == "CPU";
    if (inputs.deviceInHostMemory) {
        inputs.deviceBudgetBytes = context->memoryBudget().bytes;
        if (options.maxDeviceMemoryBytes > 0)
            inputs.deviceBudgetBytes = std::min(inputs.deviceBudgetBytes, options.maxDeviceMemoryBytes);
    }
    inputs.report = measuresError;
    inputs.outputPath = options.outputPath;
    const MemoryNeed need = estimateHostMemory(inputs);
    const HostMemory available = hostMemoryFor(options);
    checkHostMemory(need, available);
    memory.hostEstimateBytes = need.total();
    memory.hostAvailableBytes = available.bytes;
}

// The scene's or the settings' warnings, one line each.
void warn(const Options& options, const std::vector<std::string>& warnings) {
    if (options.quiet) return;
    for (const std::string& warning : warnings) {
        std::fprintf(stderr, "vkrt: warning: %s: %s\n", options.scenePath.c_str(), warning.c_str());
    }
}

}  // namespace

PreparedRender prepareRender(const Options& options, const MpiJob& job, RunReport& report) {
    PreparedRender prepared;

    // The scene, its environment and the time they took: when rendering on the GPU, loaded on another thread
    // while this one makes the Vulkan device (loading the driver takes tens of milliseconds, lavapipe's LLVM
    // among it); on the CPU, here, when the future is read. The device stays on this thread: made on another,
    // lavapipe's pipeline creation took longer.
    const bool gpu = options.device == DeviceKind::Gpu;
    std::future<Scene> loaded =
        std::async(gpu ? std::launch::async : std::launch::deferred, [&options, &report] {
            const auto loadStart = std::chrono::steady_clock::now();
            LoadOptions loadOptions;
            loadOptions.shutter = options.shutter;
            loadOptions.animation = options.animation;
            const HostMemory memory = hostMemoryFor(options);
            loadOptions.maxSceneBytes = memory.bytes;
            loadOptions.memorySource = memory.source;
            Scene scene = loadGltf(options.scenePath, loadOptions);
            if (!options.environmentPath.empty()) scene.environment = loadEnvironment(options);
            addNeutralEnvironment(options.request, scene);
            report.loadMs = millisecondsSince(loadStart);
            return scene;
        });
    std::exception_ptr contextError;
    if (gpu) {
        try {
            prepared.context = makeVulkanContext(options, job.localRank());
        } catch (...) {
            contextError = std::current_exception();
        }
    }
    prepared.scene = loaded.get();
    // Nor does a run write over the files the scene refers to (options.cpp checks the scene file itself): an
    // image written over a texture, or stats over a buffer, broke every later render of the scene.
    for (const auto& [option, output] : {std::pair{"--out", &options.outputPath},
                                         {"--stats", &options.statsPath},
                                         {"--report", &options.reportPath}}) {
        for (const std::string& file : prepared.scene.files) {
            if (!output->empty() && sameFile(*output, file))
                throw UsageError(std::string(option) +
                                 " would write over a file the scene reads: " + *output);
        }
    }
    if (!options.quiet) {
        for (const std::string& warning : options.warnings)
            std::fprintf(stderr, "vkrt: warning: %s\n", warning.c_str());
    }
    warn(options, prepared.scene.warnings);

    // Settings and camera from what was asked and what the scene holds. A scene or a request that cannot be
    // rendered is reported before a device that cannot be had, as when the two were made in turn.
    prepared.setup = resolveRender(options.request, prepared.scene);
    warn(options, prepared.setup.warnings);
    if (contextError) std::rethrow_exception(contextError);

    // Host memory, before any is spent on the render (the device's is planned by the GPU renderer).
    // Error against run time is rank 0's to ask for, and every rank of a job renders its reference then.
    const bool measuresError = job.fromRoot(!options.reportPath.empty() || !options.referencePath.empty());
    checkHostMemoryFor(options, measuresError, job.shared(), prepared.scene, prepared.setup.settings,
                       prepared.context.get(), report.memory);

    // Acceleration structure.
    prepared.bvh = buildSceneBvh(prepared.scene);
    report.bvh = prepared.bvh.stats;
    return prepared;
}

}  // namespace vkrt
