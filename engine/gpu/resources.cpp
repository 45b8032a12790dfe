#include "gpu/resources.h"

#include "base/common.h"

#include <cstring>

namespace ink {

static uint32_t findMemoryType(const Context& ctx, uint32_t typeBits, VkMemoryPropertyFlags wanted,
                               VkMemoryPropertyFlags fallback) {
    for (VkMemoryPropertyFlags flags : {wanted, fallback})
        for (uint32_t i = 0; i < ctx.memoryProperties.memoryTypeCount; ++i)
            if ((typeBits & (1u << i)) && (ctx.memoryProperties.memoryTypes[i].propertyFlags & flags) == flags)
                return i;
    throw Error("no suitable Vulkan memory type on " + std::string(ctx.properties.deviceName));
}

static VkDeviceMemory allocate(Context& ctx, const VkMemoryRequirements& req, VkMemoryPropertyFlags wanted,
                               VkMemoryPropertyFlags fallback, bool addressed = false) {
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, addressed ? &flags : nullptr};
    info.allocationSize = req.size;
    info.memoryTypeIndex = findMemoryType(ctx, req.memoryTypeBits, wanted, fallback);
    VkDeviceMemory memory;
    VK_CHECK(vkAllocateMemory(ctx.device, &info, nullptr, &memory));
    return memory;
}

Buffer createBuffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use) {
    Buffer b;
    b.size = size;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(ctx.device, &info, nullptr, &b.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device, b.buffer, &req);
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (use == MemoryUse::Device) {
        b.memory = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0,
                            (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0);
    } else {
        VkMemoryPropertyFlags cached = use == MemoryUse::Readback ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT : 0;
        b.memory = allocate(ctx, req, host | cached, host);
    }
    VK_CHECK(vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0));
    if (use != MemoryUse::Device) VK_CHECK(vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
    return b;
}

VkDeviceAddress bufferAddress(Context& ctx, const Buffer& b) {
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = b.buffer;
    return vkGetBufferDeviceAddress(ctx.device, &info);
}

void destroyBuffer(Context& ctx, Buffer& b) {
    if (b.mapped) vkUnmapMemory(ctx.device, b.memory);
    vkDestroyBuffer(ctx.device, b.buffer, nullptr);
    vkFreeMemory(ctx.device, b.memory, nullptr);
    b = Buffer{};
}

void uploadBuffer(Context& ctx, Buffer& dst, const void* data, VkDeviceSize size) {
    if (size == 0) return;
    Buffer staging = createBuffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
    std::memcpy(staging.mapped, data, size);
    submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, size};
        vkCmdCopyBuffer(cmd, staging.buffer, dst.buffer, 1, &region);
    });
    destroyBuffer(ctx, staging);
}

void uploadBufferAt(Context& ctx, Buffer& dst, VkDeviceSize offset, const void* data, VkDeviceSize size) {
    if (size == 0) return;
    Buffer staging = createBuffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
    std::memcpy(staging.mapped, data, size);
    submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT);
        VkBufferCopy region{0, offset, size};
        vkCmdCopyBuffer(cmd, staging.buffer, dst.buffer, 1, &region);
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
    destroyBuffer(ctx, staging);
}

void UploadBatch::add(Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset) {
    if (size == 0) return;
    const VkDeviceSize from = (bytes_ + 15) / 16 * 16;
    bytes_ = from + size;
    copies_.push_back({dst.buffer, data, offset, size, from});
}

void UploadBatch::submit() {
    if (copies_.empty()) return;
    Buffer staging = createBuffer(ctx_, bytes_, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
    struct Release {  // on every way out: a scan's staging buffer holds hundreds of MB
        Context& ctx;
        Buffer& staging;
        ~Release() { destroyBuffer(ctx, staging); }
    } release{ctx_, staging};
    for (const Copy& c : copies_) std::memcpy(static_cast<unsigned char*>(staging.mapped) + c.from, c.data, c.size);
    submitAndWait(ctx_, [&](VkCommandBuffer cmd) {
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT);
        for (const Copy& c : copies_) {
            VkBufferCopy region{c.from, c.offset, c.size};
            vkCmdCopyBuffer(cmd, staging.buffer, c.dst, 1, &region);
        }
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
    bytes_ = 0;
    copies_.clear();
}

void downloadBuffer(Context& ctx, const Buffer& src, VkDeviceSize offset, void* data, VkDeviceSize size) {
    if (size == 0) return;
    Buffer staging = createBuffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback);
    submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        // Whatever wrote `src` last (compute or transfer) must be visible to this copy.
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferCopy region{offset, 0, size};
        vkCmdCopyBuffer(cmd, src.buffer, staging.buffer, 1, &region);
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
    });
    std::memcpy(data, staging.mapped, size);
    destroyBuffer(ctx, staging);
}

Image createImage(Context& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect, VkSampleCountFlagBits samples) {
    Image img;
    img.format = format;
    img.extent = {width, height};
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = samples;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(ctx.device, &info, nullptr, &img.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device, img.image, &req);
    img.memory = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
    VK_CHECK(vkBindImageMemory(ctx.device, img.image, img.memory, 0));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(ctx.device, &view, nullptr, &img.view));
    return img;
}

void destroyImage(Context& ctx, Image& img) {
    vkDestroyImageView(ctx.device, img.view, nullptr);
    vkDestroyImage(ctx.device, img.image, nullptr);
    vkFreeMemory(ctx.device, img.memory, nullptr);
    img = Image{};
}

void stageBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = srcStage;
    barrier.srcAccessMask = srcAccess;
    barrier.dstStageMask = dstStage;
    barrier.dstAccessMask = dstAccess;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

void recordUniformUpdate(VkCommandBuffer cmd, const Buffer& buffer, const void* data, VkDeviceSize bytes) {
    constexpr VkPipelineStageFlags2 shaders = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT |
                                              VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT |
                                              VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    stageBarrier(cmd, shaders, 0, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdUpdateBuffer(cmd, buffer.buffer, 0, bytes, data);
    stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, shaders,
                 VK_ACCESS_2_UNIFORM_READ_BIT);
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    barrier.srcStageMask = srcStage;
    barrier.srcAccessMask = srcAccess;
    barrier.dstStageMask = dstStage;
    barrier.dstAccessMask = dstAccess;
    barrier.oldLayout = oldLayout;
    barrier.newLayout = newLayout;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {aspect, 0, 1, 0, 1};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace ink
