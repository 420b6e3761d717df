// One compute pipeline: a shader module, a descriptor set of buffers and a push-constant block. dispatch()
// checks the push-constant size and that every binding has a buffer. The constructor's time is
// kept: creating the pipeline is where the driver compiles SPIR-V to machine code (lavapipe's LLVM JIT).
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/gpu_buffer.h"
#include "gpu/vulkan_context.h"

namespace vkrt {

// How a kernel reads one of its bindings: a storage buffer, or a uniform texel buffer (read only;
// `texelFetch` of a usamplerBuffer) of four 32-bit words a texel (Texels) or of one (Words). lavapipe reads a
// storage buffer lane by lane, one component at a time, but fetches texels for all its SIMD lanes with vector
// loads (shaders/scene_arrays.glsl).
enum class BindingKind { Storage, Texels, Words };

class ComputePipeline {
  public:
    // `bindings[i]` says how binding i is read.
    ComputePipeline(const VulkanContext& context, const std::vector<uint32_t>& spirv,
                    std::vector<BindingKind> bindings, uint32_t pushConstantBytes);
    // `storageBuffers` storage-buffer bindings.
    ComputePipeline(const VulkanContext& context, const std::vector<uint32_t>& spirv, uint32_t storageBuffers,
                    uint32_t pushConstantBytes);
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    // Binds buffers[i] to binding i (a texel binding views the whole buffer as texels); the count must equal
    // the pipeline's binding count.
    void bind(const std::vector<const GpuBuffer*>& buffers);

    // Records binding the pipeline, its descriptors and push constants, and the dispatch.
    void dispatch(VkCommandBuffer commands, const void* pushConstants, uint32_t pushConstantBytes,
                  uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ = 1) const;

    // Wall time of the constructor in milliseconds: the shader module, the layouts and the pipeline.
    double createMs() const { return createMs_; }

  private:
    void releaseViews();

    const VulkanContext& context_;
    std::vector<BindingKind> bindings_;
    uint32_t pushConstantBytes_;
    bool bound_ = false;
    double createMs_ = 0.0;
    VkShaderModule module_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    std::vector<VkBufferView> views_;  // of the texel bindings, as bound
};

}  // namespace vkrt
