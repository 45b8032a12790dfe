// The Vulkan instance and device: selection (a real GPU when present, else lavapipe), validation with
// synchronization validation, and a debug messenger that counts what it reports.
#pragma once

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

// For programmer errors (a call that can only fail through a bug or an out-of-memory driver).
#define VK_CHECK(call)                                                                              \
    do {                                                                                            \
        VkResult vkCheckResult_ = (call);                                                           \
        if (vkCheckResult_ != VK_SUCCESS) ::ink::vkFail(#call, vkCheckResult_, __FILE__, __LINE__); \
    } while (0)

namespace ink {

[[noreturn]] void vkFail(const char* call, VkResult result, const char* file, int line);
const char* vkResultName(VkResult result);

struct ContextOptions {
    bool validation = false;    // validation + synchronization validation (needs vulkan-validationlayers)
    std::string device;         // "" = best; else an index ("0") or a case-insensitive substring of the name
    bool presentation = false;  // enable the surface/swapchain extensions for the viewer
    std::vector<const char*> instanceExtensions;  // extra ones (e.g. from glfwGetRequiredInstanceExtensions)
};

struct Context {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkCommandPool commandPool = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceMemoryProperties memoryProperties{};
    std::string driverInfo;  // "Mesa 22.3.6 (LLVM 15.0.6)"
    bool validation = false;

    // Counted by the debug messenger; tests and `inkwell validate` require errors == 0.
    std::atomic<uint32_t> validationErrors{0};
    std::atomic<uint32_t> validationWarnings{0};
    std::string firstValidationMessage;
};

// Throws ink::Error when there is no Vulkan driver, no device, or the requested one does not exist.
void createContext(Context& ctx, const ContextOptions& options);
void destroyContext(Context& ctx);

// The names of all devices, for error messages and `--device list`.
std::vector<std::string> listDevices();

// Records with `record`, submits to the queue and waits: for setup and readback, never between levels.
template <typename Record>
void submitAndWait(Context& ctx, Record&& record);
VkCommandBuffer beginOneTime(Context& ctx);
// Submits and waits; `whileWaiting`, when given, is called every 100 ms until the work is done (progress).
void endOneTime(Context& ctx, VkCommandBuffer cmd, const std::function<void()>& whileWaiting = {});

template <typename Record>
void submitAndWait(Context& ctx, Record&& record) {
    VkCommandBuffer cmd = beginOneTime(ctx);
    record(cmd);
    endOneTime(ctx, cmd);
}

}  // namespace ink
