#include "renderer.h"

#include "common.h"

#include <algorithm>
#include <cstring>

#include "points.frag.h"
#include "points.vert.h"

namespace ink {

StyleBlock makeStyleBlock(const RenderStyle& s, float pointSizeMin, float pointSizeMax) {
    float k = float(std::max(1u, s.supersample));
    StyleBlock b{};
    b.color[0] = s.ink;
    b.color[1] = s.ink;
    b.color[2] = s.backInk;
    b.size = glm::vec4(s.silhouetteSize * k, s.frontSize * k, s.backSize * k, s.tau);
    glm::vec3 l = glm::length(s.light) > 0 ? glm::normalize(s.light) : glm::vec3(0, 1, 0);
    b.light = glm::vec4(l, s.toneGamma);
    b.misc = glm::vec4(s.drawBack ? 1.0f : 0.0f, pointSizeMin, pointSizeMax, 0.0f);
    return b;
}

PointPipeline createPointPipeline(Context& ctx, const Buffer& points, VkFormat colorFormat, VkFormat depthFormat) {
    PointPipeline p;
    p.style = createBuffer(ctx, sizeof(StyleBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           MemoryUse::Device);
    p.descriptors = createDescriptorSet(
        ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, points.buffer}, {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, p.style.buffer}},
        VK_SHADER_STAGE_VERTEX_BIT);
    p.layout = createPipelineLayout(ctx, p.descriptors.layout, sizeof(glm::mat4) + sizeof(glm::vec4),
                                    VK_SHADER_STAGE_VERTEX_BIT);

    VkShaderModule vert = createShaderModule(ctx, spv_points_vert);
    VkShaderModule frag = createShaderModule(ctx, spv_points_frag);
    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vert;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = frag;
    stages[1].pName = "main";

    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkPipelineColorBlendAttachmentState blendAttachment{};
    blendAttachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                                     VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blendAttachment;
    VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &colorFormat;
    rendering.depthAttachmentFormat = depthFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = p.layout;
    VK_CHECK(vkCreateGraphicsPipelines(ctx.device, VK_NULL_HANDLE, 1, &info, nullptr, &p.pipeline));
    vkDestroyShaderModule(ctx.device, vert, nullptr);
    vkDestroyShaderModule(ctx.device, frag, nullptr);
    return p;
}

void destroyPointPipeline(Context& ctx, PointPipeline& p) {
    vkDestroyPipeline(ctx.device, p.pipeline, nullptr);
    vkDestroyPipelineLayout(ctx.device, p.layout, nullptr);
    destroyDescriptorSet(ctx, p.descriptors);
    destroyBuffer(ctx, p.style);
    p = PointPipeline{};
}

void drawPoints(VkCommandBuffer cmd, const PointPipeline& p, const GpuRefinement& r, const Camera& camera,
                VkExtent2D extent) {
    VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout, 0, 1, &p.descriptors.set, 0, nullptr);
    struct {
        glm::mat4 viewProj;
        glm::vec4 eye;
    } push{camera.projection(float(extent.width) / float(extent.height)) * camera.view(), glm::vec4(camera.eye(), 1)};
    vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
    vkCmdDrawIndirect(cmd, r.indirect.buffer, GpuRefinement::kDrawOffset, 1, 0);
}

OffscreenTarget createOffscreenTarget(Context& ctx, uint32_t width, uint32_t height) {
    OffscreenTarget t;
    t.color = createImage(ctx, width, height, kColorFormat,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    t.depth = createImage(ctx, width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                          VK_IMAGE_ASPECT_DEPTH_BIT);
    t.readback = createBuffer(ctx, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              MemoryUse::Readback);
    return t;
}

void destroyOffscreenTarget(Context& ctx, OffscreenTarget& t) {
    destroyImage(ctx, t.color);
    destroyImage(ctx, t.depth);
    destroyBuffer(ctx, t.readback);
}

OffscreenRenderer::OffscreenRenderer(Context& ctx, uint32_t width, uint32_t height, const RenderStyle& style,
                                     const GpuRefinement& refinement)
    : ctx_(ctx), refinement_(refinement), style_(style), width_(width), height_(height),
      factor_(std::max(1u, style.supersample)) {
    uint32_t maxSide = ctx.properties.limits.maxImageDimension2D;
    if (width == 0 || height == 0 || width * factor_ > maxSide || height * factor_ > maxSide)
        throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " (x" +
                    std::to_string(factor_) + " supersampling) is outside 1.." + std::to_string(maxSide / factor_) +
                    " on this device");
    target_ = createOffscreenTarget(ctx, width * factor_, height * factor_);
    pipeline_ = createPointPipeline(ctx, refinement.points, kColorFormat, kDepthFormat);
    setStyle(style);
}

OffscreenRenderer::~OffscreenRenderer() {
    destroyPointPipeline(ctx_, pipeline_);
    destroyOffscreenTarget(ctx_, target_);
}

void OffscreenRenderer::setStyle(const RenderStyle& style) {
    style_ = style;
    style_.supersample = factor_;
    const float* range = ctx_.properties.limits.pointSizeRange;
    StyleBlock block = makeStyleBlock(style_, range[0], range[1]);
    uploadBuffer(ctx_, pipeline_.style, &block, sizeof(block));
}

RgbaImage OffscreenRenderer::render(const Camera& camera) {
    VkExtent2D extent = target_.color.extent;
    submitAndWait(ctx_, [&](VkCommandBuffer cmd) {
        imageBarrier(cmd, target_.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
        imageBarrier(cmd, target_.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);

        VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color.imageView = target_.color.view;
        color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        color.clearValue.color = {{style_.paper.r, style_.paper.g, style_.paper.b, style_.paper.a}};
        VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depth.imageView = target_.depth.view;
        depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depth.clearValue.depthStencil = {1.0f, 0};
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &color;
        rendering.pDepthAttachment = &depth;
        vkCmdBeginRendering(cmd, &rendering);
        drawPoints(cmd, pipeline_, refinement_, camera, extent);
        vkCmdEndRendering(cmd);

        imageBarrier(cmd, target_.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, target_.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target_.readback.buffer, 1,
                               &region);
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
    });
    RgbaImage full{extent.width, extent.height, {}};
    full.pixels.resize(size_t(extent.width) * extent.height * 4);
    std::memcpy(full.pixels.data(), target_.readback.mapped, full.pixels.size());
    return downsample(full, factor_);
}

RgbaImage downsample(const RgbaImage& image, uint32_t factor) {
    if (factor <= 1) return image;
    RgbaImage out{image.width / factor, image.height / factor, {}};
    out.pixels.resize(size_t(out.width) * out.height * 4);
    const uint32_t area = factor * factor;
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (uint32_t c = 0; c < 4; ++c) {
                uint32_t sum = 0;
                for (uint32_t dy = 0; dy < factor; ++dy)
                    for (uint32_t dx = 0; dx < factor; ++dx)
                        sum += image.pixels[(size_t(y * factor + dy) * image.width + (x * factor + dx)) * 4 + c];
                out.pixels[(size_t(y) * out.width + x) * 4 + c] = uint8_t((sum + area / 2) / area);
            }
    return out;
}

}  // namespace ink
