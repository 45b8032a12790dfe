// Buffers and images: plain structs with create/destroy, plus the synchronization2 barrier helpers.
#pragma once

#include "gpu/context.h"

#include <vector>

namespace ink {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;  // set for host-visible buffers
};

enum class MemoryUse { Device, Upload, Readback };

Buffer createBuffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
void destroyBuffer(Context& ctx, Buffer& buffer);
// The device address of a buffer made with VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT (device memory only).
VkDeviceAddress bufferAddress(Context& ctx, const Buffer& buffer);
// Copies `size` bytes into a device buffer through a temporary staging buffer (setup only).
void uploadBuffer(Context& ctx, Buffer& dst, const void* data, VkDeviceSize size);
// Copies `size` bytes into a device buffer at `offset`, after whatever the device wrote there last and before
// whatever reads it next (a host edit of a buffer the device made).
void uploadBufferAt(Context& ctx, Buffer& dst, VkDeviceSize offset, const void* data, VkDeviceSize size);
// Uploads gathered for one submission: `add` notes a copy, `submit` sends them all through one staging buffer
// and one wait (setting up a refinement made seven round trips, a staging allocation, a submission and a wait
// each), with the barriers of uploadBufferAt around the copies. The data must live until submit, which copies it
// once, into the staging buffer. What is not submitted is dropped.
class UploadBatch {
public:
    explicit UploadBatch(Context& ctx) : ctx_(ctx) {}
    void add(Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset = 0);
    void submit();

private:
    struct Copy {
        VkBuffer dst;
        const void* data;
        VkDeviceSize offset, size, from;
    };
    Context& ctx_;
    VkDeviceSize bytes_ = 0;
    std::vector<Copy> copies_;
};
// Copies a device buffer range back to the host (readback for tests, exports and stats).
void downloadBuffer(Context& ctx, const Buffer& src, VkDeviceSize offset, void* data, VkDeviceSize size);

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
};

Image createImage(Context& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);
void destroyImage(Context& ctx, Image& image);

// Synchronization2 barriers: one global memory barrier between stages, or an image layout transition.
void stageBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);
// Writes `bytes` of `data` to the start of a uniform buffer in the command stream (vkCmdUpdateBuffer: at most
// 64 KiB), after the shaders of a frame still in flight have read it and before the next shaders read it.
void recordUniformUpdate(VkCommandBuffer cmd, const Buffer& buffer, const void* data, VkDeviceSize bytes);
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

}  // namespace ink
