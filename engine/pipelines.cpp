#include "pipelines.h"

#include <vector>

namespace ink {

VkShaderModule createShaderModule(Context& ctx, std::span<const uint32_t> spirv) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module;
    VK_CHECK(vkCreateShaderModule(ctx.device, &info, nullptr, &module));
    return module;
}

DescriptorSet createDescriptorSet(Context& ctx, std::initializer_list<DescriptorBinding> bindings,
                                  VkShaderStageFlags stages) {
    DescriptorSet ds;
    std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
    std::vector<VkDescriptorPoolSize> sizes;
    for (const DescriptorBinding& b : bindings) {
        layoutBindings.push_back({b.binding, b.type, b.count, stages, nullptr});
        sizes.push_back({b.type, b.count});
    }
    VkDescriptorSetLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layoutInfo.bindingCount = uint32_t(layoutBindings.size());
    layoutInfo.pBindings = layoutBindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &layoutInfo, nullptr, &ds.layout));

    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    VK_CHECK(vkCreateDescriptorPool(ctx.device, &poolInfo, nullptr, &ds.pool));

    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = ds.pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &ds.layout;
    VK_CHECK(vkAllocateDescriptorSets(ctx.device, &alloc, &ds.set));

    std::vector<std::vector<VkDescriptorBufferInfo>> infos;
    std::vector<VkWriteDescriptorSet> writes;
    for (const DescriptorBinding& b : bindings) {
        auto& elements = infos.emplace_back();
        for (uint32_t k = 0; k < b.count; ++k) {
            VkDeviceSize offset = (b.filled == 0 || k < b.filled) ? k * b.stride : 0;
            elements.push_back({b.buffer, offset, b.stride ? b.stride : VK_WHOLE_SIZE});
        }
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = ds.set;
        w.dstBinding = b.binding;
        w.descriptorCount = b.count;
        w.descriptorType = b.type;
        if (b.view)
            w.pTexelBufferView = &b.view;
        else
            w.pBufferInfo = elements.data();
        writes.push_back(w);
    }
    vkUpdateDescriptorSets(ctx.device, uint32_t(writes.size()), writes.data(), 0, nullptr);
    return ds;
}

void destroyDescriptorSet(Context& ctx, DescriptorSet& ds) {
    vkDestroyDescriptorPool(ctx.device, ds.pool, nullptr);
    vkDestroyDescriptorSetLayout(ctx.device, ds.layout, nullptr);
    ds = DescriptorSet{};
}

VkPipelineLayout createPipelineLayout(Context& ctx, VkDescriptorSetLayout setLayout, uint32_t pushConstantSize,
                                      VkShaderStageFlags pushStages) {
    VkPushConstantRange range{pushStages, 0, pushConstantSize};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &setLayout;
    info.pushConstantRangeCount = pushConstantSize ? 1 : 0;
    info.pPushConstantRanges = &range;
    VkPipelineLayout layout;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &info, nullptr, &layout));
    return layout;
}

VkPipeline createComputePipeline(Context& ctx, VkPipelineLayout layout, std::span<const uint32_t> spirv) {
    VkShaderModule module = createShaderModule(ctx, spirv);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    info.layout = layout;
    VkPipeline pipeline;
    VK_CHECK(vkCreateComputePipelines(ctx.device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    vkDestroyShaderModule(ctx.device, module, nullptr);
    return pipeline;
}

}  // namespace ink
