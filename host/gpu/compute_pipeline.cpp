#include "gpu/compute_pipeline.h"

#include <chrono>
#include <string>

#include "gpu/vulkan_check.h"

namespace vkrt {

ComputePipeline::ComputePipeline(const VulkanContext& context, const std::vector<uint32_t>& spirv,
                                 uint32_t storageBuffers, uint32_t pushConstantBytes)
    : context_(context), storageBuffers_(storageBuffers), pushConstantBytes_(pushConstantBytes) {
    const auto start = std::chrono::steady_clock::now();
    const VkDevice device = context.device();
    if (pushConstantBytes > context.properties().limits.maxPushConstantsSize) {
        throw GpuError("push constants of " + std::to_string(pushConstantBytes) +
                       " bytes exceed the device's " +
                       std::to_string(context.properties().limits.maxPushConstantsSize));
    }
    VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    moduleInfo.codeSize = spirv.size() * sizeof(uint32_t);
    moduleInfo.pCode = spirv.data();
    VK_CHECK(vkCreateShaderModule(device, &moduleInfo, nullptr, &module_));

    std::vector<VkDescriptorSetLayoutBinding> bindings(storageBuffers);
    for (uint32_t i = 0; i < storageBuffers; ++i) {
        bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    }
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = storageBuffers;
    setInfo.pBindings = bindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout_));

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &setLayout_;
    layoutInfo.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout_));

    VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipelineInfo.stage.module = module_;
    pipelineInfo.stage.pName = "main";
    pipelineInfo.layout = layout_;
    VK_CHECK(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &pipeline_));

    const VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, storageBuffers};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &poolSize;
    VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool_));
    VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocate.descriptorPool = pool_;
    allocate.descriptorSetCount = 1;
    allocate.pSetLayouts = &setLayout_;
    VK_CHECK(vkAllocateDescriptorSets(device, &allocate, &set_));
    createMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ComputePipeline::~ComputePipeline() {
    const VkDevice device = context_.device();
    vkDestroyDescriptorPool(device, pool_, nullptr);
    vkDestroyPipeline(device, pipeline_, nullptr);
    vkDestroyPipelineLayout(device, layout_, nullptr);
    vkDestroyDescriptorSetLayout(device, setLayout_, nullptr);
    vkDestroyShaderModule(device, module_, nullptr);
}

void ComputePipeline::bind(const std::vector<const GpuBuffer*>& buffers) {
    if (buffers.size() != storageBuffers_) {
        throw GpuError("pipeline has " + std::to_string(storageBuffers_) + " storage-buffer bindings but " +
                       std::to_string(buffers.size()) + " buffers were given");
    }
    std::vector<VkDescriptorBufferInfo> infos(buffers.size());
    std::vector<VkWriteDescriptorSet> writes(buffers.size());
    for (uint32_t i = 0; i < buffers.size(); ++i) {
        if (!buffers[i] || !*buffers[i]) throw GpuError("binding " + std::to_string(i) + " has no buffer");
        infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = set_;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(context_.device(), static_cast<uint32_t>(writes.size()), writes.data(), 0,
                           nullptr);
    bound_ = true;
}

void ComputePipeline::dispatch(VkCommandBuffer commands, const void* pushConstants,
                               uint32_t pushConstantBytes, uint32_t groupsX, uint32_t groupsY,
                               uint32_t groupsZ) const {
    if (pushConstantBytes != pushConstantBytes_) {
        throw GpuError("dispatch with " + std::to_string(pushConstantBytes) +
                       " bytes of push constants, pipeline takes " + std::to_string(pushConstantBytes_));
    }
    if (!bound_ && storageBuffers_ > 0) throw GpuError("dispatch before its buffers were bound");
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
    if (pushConstantBytes > 0) {
        vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes,
                           pushConstants);
    }
    vkCmdDispatch(commands, groupsX, groupsY, groupsZ);
}

}  // namespace vkrt
