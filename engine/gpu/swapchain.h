// A window's swapchain for the viewer. The surface comes from the
// windowing library (the engine knows no windows); presentation is FIFO, which every driver has.
#pragma once

#include "gpu/resources.h"

#include <cstdint>
#include <vector>

namespace ink {

struct Swapchain {
    VkSwapchainKHR swapchain = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    bool copyable = false;    // the images can be copied from (screenshots)
    bool copyTarget = false;  // and into (the viewer's panel, drawn once and copied in every frame)
    std::vector<VkImage> images;
    std::vector<VkImageView> views;
    // One per image, signalled by the frame's submission and waited on by its presentation: a semaphore
    // handed to vkQueuePresentKHR is only known to be free again when its image is acquired once more.
    std::vector<VkSemaphore> rendered;
};

// Throws ink::Error when the context's queue family cannot present to `surface`.
void checkPresentSupport(const Context& ctx, VkSurfaceKHR surface);

// B8G8R8A8_UNORM or R8G8B8A8_UNORM when offered: UNORM so that ink and paper colours reach the screen as
// the offscreen PNGs have them (an SRGB swapchain would re-encode them lighter). Else the first format.
VkSurfaceFormatKHR chooseSurfaceFormat(const Context& ctx, VkSurfaceKHR surface);

// Creates the swapchain, or recreates it in place (after waiting for the device to be idle) when it
// exists. `framebuffer` is the window's size in pixels, used where the surface leaves the size to us.
// Returns false and creates nothing while the surface has no area (a minimized window): try again later.
bool createSwapchain(Context& ctx, Swapchain& sc, VkSurfaceKHR surface, VkSurfaceFormatKHR format,
                     VkExtent2D framebuffer);
void destroySwapchain(Context& ctx, Swapchain& sc);

// Converts pixels copied from a swapchain image of `format` to RGBA in place; throws ink::Error for a
// format that is not 8-bit RGBA or BGRA.
void swizzleToRgba(VkFormat format, std::vector<uint8_t>& pixels);

}  // namespace ink
