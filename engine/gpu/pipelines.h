// Shader modules from the SPIR-V embedded at build time, descriptor sets of storage/uniform buffers,
// and compute pipelines.
#pragma once

#include "gpu/context.h"

#include <initializer_list>
#include <span>
#include <vector>

namespace ink {

VkShaderModule createShaderModule(Context& ctx, std::span<const uint32_t> spirv);

struct DescriptorBinding {
    uint32_t binding;
    VkDescriptorType type;
    VkBuffer buffer;
    uint32_t count = 1;                  // an array of `count` descriptors...
    VkDeviceSize stride = 0;             // ...element k at offset k·stride, range stride (0: the whole buffer)
    uint32_t filled = 0;                 // elements past this many repeat element 0 (0: all are distinct)
    VkBufferView view = VK_NULL_HANDLE;  // for texel buffer descriptors (then `buffer` is unused)
};

// One set layout, one pool and one set holding the given buffers.
struct DescriptorSet {
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
};
DescriptorSet createDescriptorSet(Context& ctx, std::initializer_list<DescriptorBinding> bindings,
                                  VkShaderStageFlags stages);
DescriptorSet createDescriptorSet(Context& ctx, const std::vector<DescriptorBinding>& bindings,
                                  VkShaderStageFlags stages);
void destroyDescriptorSet(Context& ctx, DescriptorSet& set);

VkPipelineLayout createPipelineLayout(Context& ctx, VkDescriptorSetLayout setLayout, uint32_t pushConstantSize,
                                      VkShaderStageFlags pushStages);
// `constants` are the specialization constants constant_id = 0, 1, ... (32-bit each).
VkPipeline createComputePipeline(Context& ctx, VkPipelineLayout layout, std::span<const uint32_t> spirv,
                                 std::span<const uint32_t> constants = {});

// A graphics pipeline for dynamic rendering into one colour attachment of `colorFormat`: triangles from the vertex
// index alone (no vertex input), no culling or depth, blended into the target by `op` (occlusion is decided in
// compute), dynamic viewport and scissor. VK_BLEND_OP_ADD: alpha over the target; VK_BLEND_OP_MIN / _MAX: the
// darker / lighter of the fragment's colour and the target's, so that overlapping fragments blend only once.
VkPipeline createBlendedPipeline(Context& ctx, VkPipelineLayout layout, VkFormat colorFormat,
                                 std::span<const uint32_t> vertex, std::span<const uint32_t> fragment,
                                 VkBlendOp op = VK_BLEND_OP_ADD);

}  // namespace ink
