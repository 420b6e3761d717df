#include "gpu/compute_pipeline.h"

#include <chrono>
#include <string>
#include <utility>

#include "gpu/vulkan_check.h"

namespace vkrt {

namespace {

VkDescriptorType descriptorType(BindingKind kind) {
    return kind == BindingKind::Storage ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                        : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
}

}  // namespace

ComputePipeline::ComputePipeline(const VulkanContext& context, const std::vector<uint32_t>& spirv,
                                 uint32_t storageBuffers, uint32_t pushConstantBytes)
    : ComputePipeline(context, spirv, std::vector<BindingKind>(storageBuffers, BindingKind::Storage),
                      pushConstantBytes) {}

ComputePipeline::ComputePipeline(const VulkanContext& context, const std::vector<uint32_t>& spirv,
                                 std::vector<BindingKind> bindingKinds, uint32_t pushConstantBytes)
    : context_(context), bindings_(std::move(bindingKinds)), pushConstantBytes_(pushConstantBytes) {
    const uint32_t count = static_cast<uint32_t>(bindings_.size());
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

    std::vector<VkDescriptorSetLayoutBinding> bindings(count);
    uint32_t texelBindings = 0;
    for (uint32_t i = 0; i < count; ++i) {
        bindings[i] = {i, descriptorType(bindings_[i]), 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
        if (bindings_[i] != BindingKind::Storage) ++texelBindings;
    }
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = count;
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

    std::vector<VkDescriptorPoolSize> poolSizes;
    if (count > texelBindings)
        poolSizes.push_back({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, count - texelBindings});
    if (texelBindings > 0) poolSizes.push_back({VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, texelBindings});
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = static_cast<uint32_t>(poolSizes.size());
    poolInfo.pPoolSizes = poolSizes.data();
    VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool_));
    VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocate.descriptorPool = pool_;
    allocate.descriptorSetCount = 1;
    allocate.pSetLayouts = &setLayout_;
    VK_CHECK(vkAllocateDescriptorSets(device, &allocate, &set_));
    createMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ComputePipeline::~ComputePipeline() {
    releaseViews();
    const VkDevice device = context_.device();
    vkDestroyDescriptorPool(device, pool_, nullptr);
    vkDestroyPipeline(device, pipeline_, nullptr);
    vkDestroyPipelineLayout(device, layout_, nullptr);
    vkDestroyDescriptorSetLayout(device, setLayout_, nullptr);
    vkDestroyShaderModule(device, module_, nullptr);
}

void ComputePipeline::releaseViews() {
    for (const VkBufferView view : views_) vkDestroyBufferView(context_.device(), view, nullptr);
    views_.clear();
}

void ComputePipeline::bind(const std::vector<const GpuBuffer*>& buffers) {
    if (buffers.size() != bindings_.size()) {
        throw GpuError("pipeline has " + std::to_string(bindings_.size()) + " bindings but " +
                       std::to_string(buffers.size()) + " buffers were given");
    }
    releaseViews();
    std::vector<VkDescriptorBufferInfo> infos(buffers.size());
    std::vector<VkBufferView> views(buffers.size(), VK_NULL_HANDLE);
    std::vector<VkWriteDescriptorSet> writes(buffers.size());
    for (uint32_t i = 0; i < buffers.size(); ++i) {
        if (!buffers[i] || !*buffers[i]) throw GpuError("binding " + std::to_string(i) + " has no buffer");
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = set_;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = descriptorType(bindings_[i]);
        if (bindings_[i] == BindingKind::Storage) {
            infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
            writes[i].pBufferInfo = &infos[i];
            continue;
        }
        const bool words = bindings_[i] == BindingKind::Words;
        const VkDeviceSize texelBytes = words ? 4 : 16;
        const VkDeviceSize texels = buffers[i]->size() / texelBytes;
        if (texels > context_.properties().limits.maxTexelBufferElements) {
            throw GpuError("binding " + std::to_string(i) + " holds " + std::to_string(texels) +
                           " texels, more than the device's " +
                           std::to_string(context_.properties().limits.maxTexelBufferElements));
        }
        VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        viewInfo.buffer = buffers[i]->handle();
        viewInfo.format = words ? VK_FORMAT_R32_UINT : VK_FORMAT_R32G32B32A32_UINT;
        viewInfo.range = texels * texelBytes;
        VK_CHECK(vkCreateBufferView(context_.device(), &viewInfo, nullptr, &views[i]));
        views_.push_back(views[i]);
        writes[i].pTexelBufferView = &views[i];
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
    if (!bound_ && !bindings_.empty()) throw GpuError("dispatch before its buffers were bound");
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
    if (pushConstantBytes > 0) {
        vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes,
                           pushConstants);
    }
    vkCmdDispatch(commands, groupsX, groupsY, groupsZ);
}

}  // namespace vkrt
