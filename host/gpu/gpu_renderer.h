// The GPU tracer: uploads the scene, compiles the shader variant the scene needs, and renders in passes of
// bounded length (so a real GPU's watchdog never fires), accumulating samples on the device and adding them
// up on the host from time to time. An image whose accumulation does not fit beside the scene is rendered in
// tiles (bands of rows) that share one device buffer.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "bvh/flat_bvh.h"
#include "common/render_settings.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device_memory_plan.h"
#include "gpu/dispatch_planner.h"
#include "gpu/gpu_buffer.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "gpu/shader_compiler.h"
#include "gpu/vulkan_context.h"
#include "gpu/workgroup_order.h"
#include "image/render_result.h"
#include "scene/scene.h"

namespace vkrt {

struct GpuRenderOptions {
    // Each dispatch is sized to take about this long; 0: chosen from the device (50 ms on a GPU, 100 on a CPU
    // device such as lavapipe; gpu_renderer.cpp's plannerFor).
    double targetDispatchMs = 0.0;
    // Invocations a dispatch keeps at least (whole rows) when it takes several samples a pixel, so that the
    // device still has enough of them to run at once; 0: chosen from the device (16,384 on a CPU device such
    // as lavapipe, 2^18 on a GPU).
    uint32_t minDispatchInvocations = 0;
    // Which tiles of a band of rows a dispatch's workgroups take (gpu/workgroup_order.h); Auto: by the
    // device.
    WorkgroupOrder workgroupOrder = WorkgroupOrder::Auto;
    std::string shaderCacheDir = defaultShaderCacheDir();
    bool allFeatures = false;          // compile every feature path, needed or not (for tests)
    SceneAccess sceneAccess = SceneAccess::Auto;  // how kernels read the scene (where it fits)
    bool subgroupCounters = true;      // sum ray counts across subgroups where the device can (for tests)
    uint64_t maxDeviceMemoryBytes = 0;  // at most this much device memory (0: what the device offers)
    // The device's sums are added into the host's at least this often (and at checkpoints, tile changes and
    // the end), so that a lost device loses about this much work at most, but no more often than once per 20
    // times a copy's cost; 0: after every dispatch.
    double hostCopyEveryMs = 10000.0;
    // Testing aid: the device is lost (DeviceLostError) at this dispatch, counting from 1; 0: never.
    uint32_t simulateDeviceLossAtDispatch = 0;
};

struct GpuRenderReport {
    double gpuMs = 0.0;  // summed timestamp intervals of the tracing dispatches (0 without timestamps)
    double compileMs = 0.0;   // GLSL to SPIR-V (glslang), or reading the SPIR-V from the cache
    double pipelineMs = 0.0;  // creating the pipeline: the driver's own compilation (lavapipe: its NIR passes)
    // Making the renderer, all of it (the scene packed, the shader and pipeline made while another thread
    // writes the scene's buffers, the image's buffers), and two of its parts.
    double setupMs = 0.0;
    double packMs = 0.0;        // the scene packed into the arrays the kernels read (GpuSceneData)
    double sceneWriteMs = 0.0;  // those arrays written into device buffers, texels and mipmaps included
    bool shaderFromCache = false;
    std::string shaderKey;
    uint32_t dispatches = 0;
    double targetDispatchMs =
        0.0;  // what each dispatch was sized to take (GpuRenderOptions, or the device's)
    double longestDispatchMs = 0.0;
    double dispatchWallMs = 0.0;         // the dispatches from submission to the host's wake-up, all together
    uint32_t mostSamplesInDispatch = 0;  // the most samples a pixel that one dispatch traced
    uint32_t loopPassesPerSample = 0;    // lavapipe: the most loop passes a lane took a sample; else 0
    uint64_t deviceMemoryBytes = 0;  // peak device memory held by vkrt's buffers
    DeviceMemoryPlan memory;         // the estimate made before allocating, and the tiles
    uint32_t hostCopies = 0;         // times the device's sums were added into the host's
    double hostCopyMs = 0.0;         // those copies' time: reading the device's sums back, adding, zeroing
    std::string deviceLost;          // why the device was lost, when it was (the render then ends early)
    SceneAccess sceneAccess = SceneAccess::Addresses;  // how the kernel read the scene's arrays
    WorkgroupOrder workgroupOrder = WorkgroupOrder::InOrder;  // which tiles the workgroups took
};

class GpuRenderer {
  public:
    GpuRenderer(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                const RenderSettings& settings, const GpuRenderOptions& options = {});
    ~GpuRenderer();

    // Renders every sample, or until `stop` says so (checked after each dispatch). With a checkpoint
    // callback, it is also called with the image so far at every power-of-two sample count, at the end, and
    // after any pass that crosses checkpointEveryMs (> 0). A lost device ends the render with the samples the
    // host had copied (StopReason::DeviceLost, report().deviceLost).
    RenderResult render(const ProgressCallback& progress = {}, const CheckpointCallback& checkpoint = {},
                        double checkpointEveryMs = 0.0, StopCondition stop = {});

    // Adds samples [firstSample, endSample) of every pixel into `sums` (rgb sums and finite-sample counts,
    // one per pixel, row by row), or stops part way when `stop` says so (its clock is the caller's: not
    // restarted). The result has no image; its sample counts are those of this range. Called again and again
    // on one renderer (the pipeline is built once), as ranks sharing a render do: a sample's value does not
    // depend on who renders it. A lost device throws DeviceLostError.
    RenderResult renderSamples(uint32_t firstSample, uint32_t endSample, std::vector<glm::dvec4>& sums,
                               const StopCondition& stop = {});

    const GpuRenderReport& report() const { return report_; }
    const SceneFeatures& features() const { return data_.features; }
    const std::vector<std::string>& defines() const { return defines_; }
    const std::vector<uint32_t>& spirv() const { return spirv_; }

  private:
    // Samples [first, end) of every pixel into `sums`, in passes (checkpoints at the schedule's sample
    // counts, counted from 0).
    RenderResult renderRange(uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums,
                             const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                             double checkpointEveryMs, const StopCondition& stop);
    // Records and runs one dispatch; returns its wall time in milliseconds.
    double runDispatch(uint32_t sampleStart, uint32_t sampleCount, uint32_t rowStart, uint32_t rowCount);
    void readCounters(RayCounters& counters);
    // Adds the device's sums of the rows dispatched since the last copy into sums_, and zeroes them there.
    void copyToHost();
    // Whether a copy is due by time (GpuRenderOptions::hostCopyEveryMs).
    bool copyDue() const;
    // Samples [first, end) of rows [tile, tileEnd); returns why it stopped early, if it did.
    StopReason renderTile(uint32_t tile, uint32_t tileEnd, uint32_t first, uint32_t end, uint64_t totalUnits,
                          const StopCondition& stop, const ProgressCallback& progress, RayCounters& rays);

    const VulkanContext& context_;
    RenderSettings settings_;
    GpuRenderOptions options_;
    std::chrono::steady_clock::time_point constructed_ = std::chrono::steady_clock::now();  // before data_
    GpuSceneData data_;
    std::vector<std::string> defines_;
    std::vector<uint32_t> spirv_;
    std::unique_ptr<ComputePipeline> pipeline_;
    std::unique_ptr<GpuSceneBuffers> sceneBuffers_;
    GpuBuffer accumulation_;            // one tile of the image: sum and compensation per pixel
    glm::dvec4* sums_ =
        nullptr;  // the whole image on the host, the render's: rgb sums and finite-sample counts
    std::vector<uint32_t> rowSamples_;  // samples dispatched for each row
    std::vector<uint32_t> rowSamplesCopied_;  // of those, the ones in sums_
    GpuBuffer counters_;
    GpuBuffer params_;
    std::unique_ptr<GpuTimer> timer_;
    uint32_t lastCounters_[VKRT_COUNTER_COUNT] = {};
    uint32_t tileRowStart_ = 0;  // the tile the dispatches accumulate into
    uint32_t dirtyBegin_ = UINT32_MAX, dirtyEnd_ = 0;  // image rows dispatched since the last copy
    std::chrono::steady_clock::time_point lastCopy_;
    double lastCopyMs_ = 0.0;    // what the last copy cost
    DispatchPlanner planner_;    // rows x samples a dispatch, from the times measured so far
    SpreadGrid tiles_;           // a band's tiles as the dispatch's workgroups take them (workgroup_order.h)
    uint64_t unitsDone_ = 0;     // rows x samples dispatched in this render
    GpuRenderReport report_;
};

}  // namespace vkrt
