// The viewer's own Vulkan, beside Inkwell's on the same device (inkwell::Device::handles): the window's swapchain,
// the panel's images, barriers and one-off submissions. Inkwell draws into the swapchain's images through its
// FrameRecorder; everything else on the screen is the viewer's.
#pragma once

#include "inkwell/inkwell.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

// For calls that fail only through a bug or a driver out of memory: throws inkwell::Error naming the call.
#define VIEWER_CHECK(call)                                                                                     \
    do {                                                                                                       \
        VkResult viewerCheckResult_ = (call);                                                                  \
        if (viewerCheckResult_ != VK_SUCCESS) ::viewer::vkFail(#call, viewerCheckResult_, __FILE__, __LINE__); \
    } while (0)

namespace viewer {

[[noreturn]] void vkFail(const char* call, VkResult result, const char* file, int line);
std::string resultName(VkResult result);

// The device's handles and what the viewer made on it for itself: a command pool for its one-off submissions.
struct Gpu {
    inkwell::AdoptedDevice vk;
    std::string name;
    VkPhysicalDeviceMemoryProperties memory{};
    VkCommandPool pool = VK_NULL_HANDLE;
    explicit Gpu(const inkwell::Device& device);
    ~Gpu();
    Gpu(const Gpu&) = delete;
    Gpu& operator=(const Gpu&) = delete;
};

// Records with `record`, submits to the queue and waits (setup only: the panel's font texture).
void submitAndWait(const Gpu& gpu, const std::function<void(VkCommandBuffer)>& record);

// A device-local 2D colour image with its view.
struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkExtent2D extent{};
};
Image createImage(const Gpu& gpu, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage);
void destroyImage(const Gpu& gpu, Image& image);

// A synchronization2 image layout transition of the colour aspect.
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout oldLayout, VkImageLayout newLayout,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess);

struct Swapchain {
    VkSwapchainKHR swapchain = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    bool copyable = false;    // the images can be copied from (screenshots)
    bool copyTarget = false;  // and into (the panel, drawn once and copied in every frame)
    std::vector<VkImage> images;
    std::vector<VkImageView> views;
    // One per image, signalled by the frame's submission and waited on by its presentation: a semaphore
    // handed to vkQueuePresentKHR is only known to be free again when its image is acquired once more.
    std::vector<VkSemaphore> rendered;
};

// Throws inkwell::Error when the device's queue family cannot present to `surface`.
void checkPresentSupport(const Gpu& gpu, VkSurfaceKHR surface);
// B8G8R8A8_UNORM or R8G8B8A8_UNORM when offered: UNORM so that ink and paper colours reach the screen as the
// offscreen PNGs have them (an SRGB swapchain would re-encode them lighter). Else the first format, and `warning`
// says so.
VkSurfaceFormatKHR chooseSurfaceFormat(const Gpu& gpu, VkSurfaceKHR surface, std::string& warning);
// Creates the swapchain, or recreates it in place (after waiting for the device to be idle) when it exists, FIFO.
// `framebuffer` is the window's size in pixels, used where the surface leaves the size to us. Returns false and
// creates nothing while the surface has no area (a minimized window): try again later.
bool createSwapchain(const Gpu& gpu, Swapchain& sc, VkSurfaceKHR surface, VkSurfaceFormatKHR format,
                     VkExtent2D framebuffer);
void destroySwapchain(const Gpu& gpu, Swapchain& sc);

}  // namespace viewer
