// The Vulkan instance and device: selection (a real GPU when present, else lavapipe), validation with
// synchronization validation, and a debug messenger that counts what it reports.
#pragma once

#include "inkwell/inkwell.h"

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
    // Called with each validation error (true) or warning (false); the library prints nothing itself.
    std::function<void(bool error, const std::string& message)> validationMessage;
    // Enable shaderFloat64 where the device has it (only `--fit global` uses double); tests turn it off to run
    // as on a device without it.
    bool float64 = true;
};

// A device the caller made and keeps: the public type (include/inkwell/inkwell.h says what it must have).
using AdoptedDevice = inkwell::AdoptedDevice;

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
    VkDriverId driverId{};   // picks device-specific code paths (lavapipe's stamped pen lines, strokes.cpp)
    bool float64 = false;    // shaderFloat64 enabled: the global fit's double evaluation can run
    // bufferDeviceAddress enabled: a model whose patch nodes outgrow maxStorageBufferRange reads them by address
    // (refine.cpp), up to maxBufferSize.
    bool bufferDeviceAddress = false;
    VkDeviceSize maxBufferSize = 0;  // the most one buffer (and one allocation) may hold
    uint32_t maxSubgroupSize = 0;    // the largest a compute dispatch's subgroups may be
    bool validation = false;
    bool ownsDevice = true;  // false for an adopted device: destroyContext leaves it to its owner
    std::function<void(bool error, const std::string& message)> validationMessage;

    // Counted by the debug messenger; tests and `inkwell validate` require errors == 0.
    std::atomic<uint32_t> validationErrors{0};
    std::atomic<uint32_t> validationWarnings{0};
    std::string firstValidationMessage;
};

// Throws ink::Error when there is no Vulkan driver, no device, or the requested one does not exist.
void createContext(Context& ctx, const ContextOptions& options);
// Uses the caller's device: only the engine's command pool is made on it. Throws ink::Error when the device
// lacks what the shaders use.
void adoptContext(Context& ctx, const AdoptedDevice& device);
// Waits for the queue and destroys what the engine made (and the device and instance when it made them).
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
