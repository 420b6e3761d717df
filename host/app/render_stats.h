// The statistics JSON written by --stats.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bvh/bvh.h"
#include "common/render_settings.h"
#include "common/stop_condition.h"

namespace vkrt {

class FileBatch;

struct RunReport {
    std::string scene;
    std::string device;
    std::string camera;
    size_t triangles = 0;
    size_t spheres = 0;       // VKRT_sphere
    size_t solids = 0;        // VKRT_shape and VKRT_csg objects
    size_t shapes = 0;        // their shapes
    size_t textureBytes = 0;  // texels of the scene's textures (RGBA8) and their mipmaps, as both renderers hold them
    RenderSettings settings;
    // The --environment map; absent without one.
    struct Environment {
        // The uniform radiance that stands in for a map (a scene without lights, or paths' --ambient), else a
        // map read from `file`.
        std::optional<glm::dvec3> uniformRadiance;
        std::string file;
        int width = 0;
        int height = 0;
        double rotationDegrees = 0.0;
        double strength = 1.0;
    };
    std::optional<Environment> environment;
    BvhStats bvh;
    double loadMs = 0.0;
    double renderMs = 0.0;
    RayCounters rays;
    // Samples per pixel rendered: every pixel has at least samplesRendered, some up to mostSamplesRendered
    // when the render stopped part way through a pass (by the time limit or an interrupt).
    int samplesRendered = 0;
    int mostSamplesRendered = 0;
    StopReason stopped = StopReason::None;
    std::string deviceLost;  // why the GPU render ended early, when its device was lost

    // Memory: estimated before the render, and what there was.
    struct Memory {
        uint64_t hostEstimateBytes = 0;
        uint64_t hostAvailableBytes = 0;
        uint64_t hostPeakBytes = 0;        // the process's peak resident memory, scene and all
        uint64_t hostHugePageBytes = 0;    // of its memory, what is on transparent huge pages at the end
        uint64_t deviceEstimateBytes = 0;  // GPU only
        uint64_t deviceBudgetBytes = 0;
        uint32_t tiles = 0;
        uint32_t tileRows = 0;
        uint32_t hostCopies = 0;  // times the device's sums were added into the host's
    };
    Memory memory;

    // The GPU tracer's own figures; absent for the CPU reference.
    struct Gpu {
        std::string deviceName;
        std::string deviceType;
        std::string driver;
        double gpuMs = 0.0;
        double compileMs = 0.0;   // GLSL to SPIR-V by glslang, or the SPIR-V read from the cache
        double pipelineMs = 0.0;  // pipeline creation: the driver's compilation of the SPIR-V
        double setupMs = 0.0;     // making the renderer, all of it (GpuRenderReport::setupMs)
        double packMs = 0.0;      // of which packing the scene's arrays
        double sceneWriteMs = 0.0;  // and writing them into device buffers (beside the shader's making)
        bool shaderFromCache = false;
        bool allFeatures = false;  // --shader-features all: every feature compiled in, not just the scene's
        size_t spirvBytes = 0;
        std::string shaderKey;  // the SPIR-V cache's key: the same key, the same shader
        std::vector<std::string> features;
        uint64_t deviceMemoryBytes = 0;
        uint32_t dispatches = 0;
        double longestDispatchMs = 0.0;
        double dispatchWallMs = 0.0;         // all dispatches, submission to wake-up
        double hostCopyMs = 0.0;             // reading the device's sums back into the host's
        double targetDispatchMs = 0.0;       // what each dispatch was sized to take
        uint32_t mostSamplesInDispatch = 0;  // the most samples a pixel one dispatch traced
        uint32_t loopPassesPerSample = 0;    // lavapipe: the most loop passes a lane took a sample
        std::string sceneAccess;  // how kernels read the scene (gpu_scene.h sceneAccessName)
        std::string workgroupOrder;  // which tiles a dispatch's workgroups took (gpu/workgroup_order.h)
    };
    std::optional<Gpu> gpu;

    // Under MPI, every rank's share of the render, in rank order (empty for one process).
    struct Rank {
        std::string device;      // "gpu" or "cpu"
        std::string deviceName;  // the Vulkan device's name, or "cpu reference"
        uint64_t samples = 0;    // samples per pixel it rendered (at least; at most samplesMax)
        uint64_t samplesMax = 0;
        uint32_t batches = 0;
        RayCounters rays;
        double renderMs = 0.0;
    };
    std::vector<Rank> ranks;
};

nlohmann::json toJson(const RunReport& report);

// Writes the JSON atomically (a temporary file renamed into place).
void writeJson(const nlohmann::json& json, const std::string& path);

// The same, renamed into place by `batch` with the files written beside it.
void stageJson(FileBatch& batch, const nlohmann::json& json, const std::string& path);

}  // namespace vkrt
