// Traces batches of rays on the GPU with the renderer's own traversal (shaders/raycast.comp): closest hit
// or any hit. For ray-level conformance tests and ray-throughput benchmarks.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bvh/flat_bvh.h"
#include "gpu/compute_pipeline.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "gpu/vulkan_context.h"
#include "gpu/workgroup_order.h"

namespace vkrt {

enum class RaycastMode : uint32_t { Closest, Any };

// One trace's times; with `repeats`, each is that of the whole submission divided by the repeats.
struct RaycastTiming {
    double gpuMs = 0.0;   // from timestamps (0 when the device has none)
    double wallMs = 0.0;  // submit to completion, as seen by the host
    double cpuMs = 0.0;   // CPU time this process spent meanwhile, all threads (a CPU device's work)
};

class GpuRaycaster {
  public:
    // `extraDefines` compile into the kernel besides the scene's (VKRT_COUNT_ITERATIONS: hits carry the
    // walk's loop iterations in u, raycast.comp). A scene-access define among them (VKRT_TEXEL_SCENE,
    // VKRT_BOUND_GEOMETRY, VKRT_ADDRESSED_SCENE) asks for that way of reading the scene (gpu_scene.h
    // SceneAccess) instead of the device's best, where the scene fits it.
    // `order`: which blocks of rays a dispatch's workgroups take (gpu/workgroup_order.h); Auto: by the
    // device.
    GpuRaycaster(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                 const std::string& shaderCacheDir, const std::vector<std::string>& extraDefines = {},
                 WorkgroupOrder order = WorkgroupOrder::Auto);
    ~GpuRaycaster();

    SceneAccess sceneAccess() const { return sceneAccess_; }
    WorkgroupOrder workgroupOrder() const { return order_; }

    // Hits are reported with scene triangle indices (not the GPU's leaf order). `repeats` > 1 traces the
    // batch that many times, back to back in one submission (the same hits each time), for a benchmark's
    // timing: a GPU traces a million rays in about a millisecond, too short to time alone (ray_benchmark).
    std::vector<gpu::GpuHit> trace(const std::vector<gpu::GpuRay>& rays, RaycastMode mode,
                                   RaycastTiming* timing = nullptr, uint32_t repeats = 1);

  private:
    // The kernel of `mode` (raycast.comp has one per mode), compiled at its first use.
    ComputePipeline& pipelineFor(RaycastMode mode);

    const VulkanContext& context_;
    GpuSceneData data_;
    std::unique_ptr<GpuSceneBuffers> sceneBuffers_;
    GpuBuffer params_;
    std::string shaderCacheDir_;
    std::vector<std::string> defines_;  // the scene's and the caller's, for both kernels
    SceneAccess sceneAccess_ = SceneAccess::Addresses;
    WorkgroupOrder order_;  // which block of rays each workgroup takes
    std::vector<const GpuBuffer*> bindings_;
    std::unique_ptr<ComputePipeline> pipelines_[2];  // by RaycastMode
    std::unique_ptr<GpuTimer> timer_;
};

}  // namespace vkrt
