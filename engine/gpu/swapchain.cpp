#include "gpu/swapchain.h"

#include "base/common.h"

#include <algorithm>
#include <utility>

namespace ink {

void checkPresentSupport(const Context& ctx, VkSurfaceKHR surface) {
    VkBool32 supported = VK_FALSE;
    VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice, ctx.queueFamily, surface, &supported));
    if (!supported)
        throw Error(std::string(ctx.properties.deviceName) +
                    " cannot present to this window from its graphics queue; choose another device with "
                    "--device, or use 'inkwell render' for PNG output");
}

VkSurfaceFormatKHR chooseSurfaceFormat(const Context& ctx, VkSurfaceKHR surface) {
    uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, surface, &count, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(count);
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, surface, &count, formats.data()));
    if (formats.empty()) throw Error("the window's surface offers no pixel formats");
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    note("the window offers no UNORM RGBA/BGRA format; colours may differ from 'inkwell render'");
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
static void destroyImageResources(Context& ctx, Swapchain& sc) {
    for (VkImageView v : sc.views) vkDestroyImageView(ctx.device, v, nullptr);
    for (VkSemaphore s : sc.rendered) vkDestroySemaphore(ctx.device, s, nullptr);
    sc.views.clear();
    sc.rendered.clear();
    sc.images.clear();
}

static void createImageResources(Context& ctx, Swapchain& sc) {
    uint32_t count = 0;
    VK_CHECK(vkGetSwapchainImagesKHR(ctx.device, sc.swapchain, &count, nullptr));
    sc.images.resize(count);
    VK_CHECK(vkGetSwapchainImagesKHR(ctx.device, sc.swapchain, &count, sc.images.data()));
    for (VkImage image : sc.images) {
        VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        info.image = image;
        info.viewType = VK_IMAGE_VIEW_TYPE_2D;
        info.format = sc.format;
        info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view;
        VK_CHECK(vkCreateImageView(ctx.device, &info, nullptr, &view));
        sc.views.push_back(view);
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore semaphore;
        VK_CHECK(vkCreateSemaphore(ctx.device, &semaphoreInfo, nullptr, &semaphore));
        sc.rendered.push_back(semaphore);
    }
}

bool createSwapchain(Context& ctx, Swapchain& sc, VkSurfaceKHR surface, VkSurfaceFormatKHR format,
                     VkExtent2D framebuffer) {
    VkSurfaceCapabilitiesKHR caps;
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physicalDevice, surface, &caps));
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
    if (sc.swapchain) VK_CHECK(vkDeviceWaitIdle(ctx.device));
    VkSwapchainKHR created;
    VK_CHECK(vkCreateSwapchainKHR(ctx.device, &info, nullptr, &created));
    destroyImageResources(ctx, sc);
    if (sc.swapchain) vkDestroySwapchainKHR(ctx.device, sc.swapchain, nullptr);

    sc.swapchain = created;
    sc.format = format.format;
    sc.extent = extent;
    sc.copyable = copyable;
    sc.copyTarget = copyTarget;
    createImageResources(ctx, sc);
    return true;
}

void destroySwapchain(Context& ctx, Swapchain& sc) {
    destroyImageResources(ctx, sc);
    if (sc.swapchain) vkDestroySwapchainKHR(ctx.device, sc.swapchain, nullptr);
    sc = Swapchain{};
}

void swizzleToRgba(VkFormat format, std::vector<uint8_t>& pixels) {
    switch (format) {
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB:
            return;
        case VK_FORMAT_B8G8R8A8_UNORM:
        case VK_FORMAT_B8G8R8A8_SRGB:
            for (size_t i = 0; i + 3 < pixels.size(); i += 4) std::swap(pixels[i], pixels[i + 2]);
            return;
        default:
            throw Error("screenshots need an 8-bit RGBA or BGRA window format");
    }
}

}  // namespace ink
