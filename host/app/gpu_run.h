// The GPU tracer as a vkrt run uses it: the Vulkan device and the renderer's options from the command line
// and the environment, the renderer's figures for the stats, and the validation layer's messages as an error.
#pragma once

#include <memory>

#include "app/options.h"
#include "app/render_stats.h"
#include "gpu/gpu_renderer.h"
#include "gpu/vulkan_context.h"

namespace vkrt {

// The Vulkan device of --device-index, or the one chosen for the rank `localRank` on this machine.
// VKRT_VALIDATE=1 turns validation on without changing the command line (the test suite uses it).
std::unique_ptr<VulkanContext> makeVulkanContext(const Options& options, int localRank);

// The GPU renderer's options from the command line and the environment.
GpuRenderOptions gpuRenderOptions(const Options& options);

// The GPU tracer's figures for the stats.
RunReport::Gpu gpuReportOf(const Options& options, const VulkanContext& context, const GpuRenderer& renderer);

// The renderer's device memory, tiles and copies, and a lost device, into the run's report.
void recordDeviceMemory(const GpuRenderer& renderer, RunReport& report);

// Throws GpuError when the validation layer said anything.
void throwOnValidationMessages(const VulkanContext& context);

}  // namespace vkrt
