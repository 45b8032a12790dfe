#include "vulkan.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace viewer {

std::string resultName(VkResult result) {
    switch (result) {
#define VIEWER_RESULT(r) \
    case r:              \
        return #r;
        VIEWER_RESULT(VK_NOT_READY)
        VIEWER_RESULT(VK_TIMEOUT)
        VIEWER_RESULT(VK_INCOMPLETE)
        VIEWER_RESULT(VK_SUBOPTIMAL_KHR)
        VIEWER_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        VIEWER_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        VIEWER_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        VIEWER_RESULT(VK_ERROR_DEVICE_LOST)
        VIEWER_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        VIEWER_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        VIEWER_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        VIEWER_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        VIEWER_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        VIEWER_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        VIEWER_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        VIEWER_RESULT(VK_ERROR_SURFACE_LOST_KHR)
        VIEWER_RESULT(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        VIEWER_RESULT(VK_ERROR_OUT_OF_DATE_KHR)
#undef VIEWER_RESULT
        default:
            return "VkResult " + std::to_string(int(result));
    }
}

// As the library's: one line, and a sentence of their own for the failures a user can meet.
void vkFail(const char* call, VkResult result, const char* file, int line) {
    const char* base = std::strrchr(file, '/');
    const std::string where = std::string(base ? base + 1 : file) + ":" + std::to_string(line);
    if (result == VK_ERROR_DEVICE_LOST)
        throw inkwell::Error("the Vulkan device was lost (driver crash or GPU reset) in " + std::string(call) + " at " +
                             where);
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw inkwell::Error("out of " + std::string(result == VK_ERROR_OUT_OF_DEVICE_MEMORY ? "device" : "host") +
                             " memory in " + call + " at " + where + ": ask for fewer points or a smaller window");
    throw inkwell::Error(std::string(call) + " failed with " + resultName(result) + " at " + where);
}

Gpu::Gpu(const inkwell::Device& device) : vk(device.handles()), name(device.name()) {
    vkGetPhysicalDeviceMemoryProperties(vk.physicalDevice, &memory);
    VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    info.queueFamilyIndex = vk.queueFamily;
    VIEWER_CHECK(vkCreateCommandPool(vk.device, &info, nullptr, &pool));
}

Gpu::~Gpu() { vkDestroyCommandPool(vk.device, pool, nullptr); }

void submitAndWait(const Gpu& gpu, const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = gpu.pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VIEWER_CHECK(vkAllocateCommandBuffers(gpu.vk.device, &alloc, &cmd));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    // The command buffer goes back to the pool whatever fails; the failing call is named.
    const char* call = "vkBeginCommandBuffer";
    VkResult result = vkBeginCommandBuffer(cmd, &begin);
    if (result == VK_SUCCESS) {
        record(cmd);
        call = "vkEndCommandBuffer";
        result = vkEndCommandBuffer(cmd);
    }
    if (result == VK_SUCCESS) {
        VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cmdInfo.commandBuffer = cmd;
        VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        submit.commandBufferInfoCount = 1;
        submit.pCommandBufferInfos = &cmdInfo;
        call = "vkQueueSubmit2";
        result = vkQueueSubmit2(gpu.vk.queue, 1, &submit, VK_NULL_HANDLE);
        if (result == VK_SUCCESS) {
            call = "vkQueueWaitIdle";
            result = vkQueueWaitIdle(gpu.vk.queue);
        }
    }
    vkFreeCommandBuffers(gpu.vk.device, gpu.pool, 1, &cmd);
    if (result != VK_SUCCESS) vkFail(call, result, __FILE__, __LINE__);
}

Image createImage(const Gpu& gpu, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage) {
    VkDevice device = gpu.vk.device;
    Image img;
    img.extent = extent;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VIEWER_CHECK(vkCreateImage(device, &info, nullptr, &img.image));
    try {
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device, img.image, &req);
        uint32_t type = UINT32_MAX;
        for (VkMemoryPropertyFlags wanted : {VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT), 0u})
            for (uint32_t i = 0; i < gpu.memory.memoryTypeCount && type == UINT32_MAX; ++i)
                if ((req.memoryTypeBits & (1u << i)) && (gpu.memory.memoryTypes[i].propertyFlags & wanted) == wanted)
                    type = i;
        if (type == UINT32_MAX) throw inkwell::Error("no Vulkan memory type for the viewer's panel on " + gpu.name);
        VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        allocate.allocationSize = req.size;
        allocate.memoryTypeIndex = type;
        VIEWER_CHECK(vkAllocateMemory(device, &allocate, nullptr, &img.memory));
        VIEWER_CHECK(vkBindImageMemory(device, img.image, img.memory, 0));
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = img.image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VIEWER_CHECK(vkCreateImageView(device, &view, nullptr, &img.view));
    } catch (...) {
        destroyImage(gpu, img);
        throw;
    }
    return img;
}

void destroyImage(const Gpu& gpu, Image& img) {
    vkDestroyImageView(gpu.vk.device, img.view, nullptr);
    vkDestroyImage(gpu.vk.device, img.image, nullptr);
    vkFreeMemory(gpu.vk.device, img.memory, nullptr);
    img = Image{};
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout oldLayout, VkImageLayout newLayout,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess) {
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
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

void checkPresentSupport(const Gpu& gpu, VkSurfaceKHR surface) {
    VkBool32 supported = VK_FALSE;
    VIEWER_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(gpu.vk.physicalDevice, gpu.vk.queueFamily, surface, &supported));
    if (!supported)
        throw inkwell::Error(gpu.name +
                             " cannot present to this window from its graphics queue; choose another device with "
                             "--device, or use 'inkwell render' for PNG output");
}

VkSurfaceFormatKHR chooseSurfaceFormat(const Gpu& gpu, VkSurfaceKHR surface, std::string& warning) {
    uint32_t count = 0;
    VIEWER_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(gpu.vk.physicalDevice, surface, &count, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(count);
    VIEWER_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(gpu.vk.physicalDevice, surface, &count, formats.data()));
    if (formats.empty()) throw inkwell::Error("the window's surface offers no pixel formats");
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    warning = "the window offers no UNORM RGBA/BGRA format; colours may differ from 'inkwell render'";
    return formats.front();
}

static VkExtent2D chooseExtent(const VkSurfaceCapabilitiesKHR& caps, VkExtent2D framebuffer) {
    if (caps.currentExtent.width != UINT32_MAX) return caps.currentExtent;  // the surface decides
    return {std::clamp(framebuffer.width, caps.minImageExtent.width, caps.maxImageExtent.width),
            std::clamp(framebuffer.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
}

static VkCompositeAlphaFlagBitsKHR chooseCompositeAlpha(VkCompositeAlphaFlagsKHR supported) {
    for (VkCompositeAlphaFlagBitsKHR bit :
         {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
          VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR, VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
        if (supported & bit) return bit;
    return VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
}

// Everything but the VkSwapchainKHR itself, so that a recreation can pass the old one on as oldSwapchain.
static void destroyImageResources(const Gpu& gpu, Swapchain& sc) {
    for (VkImageView v : sc.views) vkDestroyImageView(gpu.vk.device, v, nullptr);
    for (VkSemaphore s : sc.rendered) vkDestroySemaphore(gpu.vk.device, s, nullptr);
    sc.views.clear();
    sc.rendered.clear();
    sc.images.clear();
}

static void createImageResources(const Gpu& gpu, Swapchain& sc) {
    VkDevice device = gpu.vk.device;
    uint32_t count = 0;
    VIEWER_CHECK(vkGetSwapchainImagesKHR(device, sc.swapchain, &count, nullptr));
    sc.images.resize(count);
    VIEWER_CHECK(vkGetSwapchainImagesKHR(device, sc.swapchain, &count, sc.images.data()));
    for (VkImage image : sc.images) {
        VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        info.image = image;
        info.viewType = VK_IMAGE_VIEW_TYPE_2D;
        info.format = sc.format;
        info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view;
        VIEWER_CHECK(vkCreateImageView(device, &info, nullptr, &view));
        sc.views.push_back(view);
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore semaphore;
        VIEWER_CHECK(vkCreateSemaphore(device, &semaphoreInfo, nullptr, &semaphore));
        sc.rendered.push_back(semaphore);
    }
}

bool createSwapchain(const Gpu& gpu, Swapchain& sc, VkSurfaceKHR surface, VkSurfaceFormatKHR format,
                     VkExtent2D framebuffer) {
    VkSurfaceCapabilitiesKHR caps;
    VIEWER_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(gpu.vk.physicalDevice, surface, &caps));
    VkExtent2D extent = chooseExtent(caps, framebuffer);
    if (extent.width == 0 || extent.height == 0) return false;

    // One image more than the minimum, so that acquiring never waits on the presentation engine's hold.
    uint32_t imageCount = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) imageCount = std::min(imageCount, caps.maxImageCount);
    bool copyable = caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    bool copyTarget = caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT;

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface;
    info.minImageCount = imageCount;
    info.imageFormat = format.format;
    info.imageColorSpace = format.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (copyable ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0) |
                      (copyTarget ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : 0);
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = chooseCompositeAlpha(caps.supportedCompositeAlpha);
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    info.clipped = VK_TRUE;
    info.oldSwapchain = sc.swapchain;

    // The old images may still be in use by frames in flight or by their presentation.
    if (sc.swapchain) VIEWER_CHECK(vkDeviceWaitIdle(gpu.vk.device));
    VkSwapchainKHR created;
    VIEWER_CHECK(vkCreateSwapchainKHR(gpu.vk.device, &info, nullptr, &created));
    destroyImageResources(gpu, sc);
    if (sc.swapchain) vkDestroySwapchainKHR(gpu.vk.device, sc.swapchain, nullptr);

    sc.swapchain = created;
    sc.format = format.format;
    sc.extent = extent;
    sc.copyable = copyable;
    sc.copyTarget = copyTarget;
    createImageResources(gpu, sc);
    return true;
}

void destroySwapchain(const Gpu& gpu, Swapchain& sc) {
    destroyImageResources(gpu, sc);
    if (sc.swapchain) vkDestroySwapchainKHR(gpu.vk.device, sc.swapchain, nullptr);
    sc = Swapchain{};
}

}  // namespace viewer
