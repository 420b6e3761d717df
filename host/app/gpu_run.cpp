#include "app/gpu_run.h"

#include <cstdlib>
#include <string>

#include "gpu/vulkan_check.h"

namespace vkrt {

std::unique_ptr<VulkanContext> makeVulkanContext(const Options& options, int localRank) {
    ContextOptions contextOptions;
    const char* validateEnv = std::getenv("VKRT_VALIDATE");
    contextOptions.validation = options.validate || (validateEnv && std::string(validateEnv) == "1");
    contextOptions.deviceIndex = options.deviceIndex;
    contextOptions.localRank = localRank;
    return std::make_unique<VulkanContext>(contextOptions);
}

GpuRenderOptions gpuRenderOptions(const Options& options) {
    GpuRenderOptions gpuOptions;
    gpuOptions.allFeatures = options.allShaderFeatures;
    gpuOptions.sceneAccess = options.sceneAccess == "texels"      ? SceneAccess::Texels
                             : options.sceneAccess == "storage"   ? SceneAccess::Storage
                             : options.sceneAccess == "addresses" ? SceneAccess::Addresses
                                                                  : SceneAccess::Auto;
    gpuOptions.maxDeviceMemoryBytes = options.maxDeviceMemoryBytes;
    // Testing aid: VKRT_SIMULATE_DEVICE_LOSS=N loses the device at the N-th dispatch.
    if (const char* loss = std::getenv("VKRT_SIMULATE_DEVICE_LOSS"))
        gpuOptions.simulateDeviceLossAtDispatch = static_cast<uint32_t>(std::strtoul(loss, nullptr, 10));
    return gpuOptions;
}

void recordDeviceMemory(const GpuRenderer& renderer, RunReport& report) {
    const GpuRenderReport& g = renderer.report();
    report.memory.deviceEstimateBytes = g.memory.need.total();
    report.memory.deviceBudgetBytes = g.memory.budgetBytes;
    report.memory.tiles = g.memory.tiles;
    report.memory.tileRows = g.memory.tileRows;
    report.memory.hostCopies = g.hostCopies;
    report.deviceLost = g.deviceLost;
}

RunReport::Gpu gpuReportOf(const Options& options, const VulkanContext& context,
                           const GpuRenderer& renderer) {
    const GpuRenderReport& g = renderer.report();
    RunReport::Gpu gpu;
    gpu.deviceName = context.description().name;
    gpu.deviceType = context.description().type;
    gpu.driver = context.description().driver;
    gpu.gpuMs = g.gpuMs;
    gpu.compileMs = g.compileMs;
    gpu.pipelineMs = g.pipelineMs;
    gpu.setupMs = g.setupMs;
    gpu.packMs = g.packMs;
    gpu.sceneWriteMs = g.sceneWriteMs;
    gpu.shaderFromCache = g.shaderFromCache;
    gpu.allFeatures = options.allShaderFeatures;
    gpu.spirvBytes = renderer.spirv().size() * sizeof(uint32_t);
    gpu.shaderKey = g.shaderKey;
    gpu.features = renderer.features().names();
    gpu.deviceMemoryBytes = g.deviceMemoryBytes;
    gpu.dispatches = g.dispatches;
    gpu.longestDispatchMs = g.longestDispatchMs;
    gpu.dispatchWallMs = g.dispatchWallMs;
    gpu.hostCopyMs = g.hostCopyMs;
    gpu.targetDispatchMs = g.targetDispatchMs;
    gpu.mostSamplesInDispatch = g.mostSamplesInDispatch;
    gpu.loopPassesPerSample = g.loopPassesPerSample;
    gpu.sceneAccess = sceneAccessName(g.sceneAccess);
    gpu.workgroupOrder = workgroupOrderName(g.workgroupOrder);
    return gpu;
}

void throwOnValidationMessages(const VulkanContext& context) {
    if (context.validationMessages() > 0)
        throw GpuError(std::to_string(context.validationMessages()) + " validation message(s), see above");
}

}  // namespace vkrt
