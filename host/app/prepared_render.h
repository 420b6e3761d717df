// Everything a render needs before it begins, the same for one process and for every rank of an MPI job: the
// scene and its environment loaded, the settings and camera resolved, the Vulkan device made, the host memory
// checked and the BVH built.
#pragma once

#include <memory>

#include "app/mpi_job.h"
#include "app/options.h"
#include "app/render_policy.h"
#include "app/render_stats.h"
#include "bvh/triangle_bvh.h"
#include "gpu/vulkan_context.h"
#include "scene/scene.h"

namespace vkrt {

struct PreparedRender {
    Scene scene;
    RenderSetup setup;
    std::unique_ptr<VulkanContext> context;  // null when rendering on the CPU
    TriangleBvh bvh;
};

// Prepares the render `options` ask for, saying the scene's and the settings' warnings unless --quiet;
// records the load time, the host memory estimate and the BVH's figures in `report`. Throws SceneError,
// UsageError (an --environment that cannot be used) and MemoryError (a render that does not fit).
PreparedRender prepareRender(const Options& options, const MpiJob& job, RunReport& report);

}  // namespace vkrt
