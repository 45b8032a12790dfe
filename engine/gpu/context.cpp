#include "gpu/context.h"

#include "base/common.h"

#include <algorithm>
#include <cctype>
#include <cstring>

namespace ink {

const char* vkResultName(VkResult result) {
    switch (result) {
#define INK_RESULT(r) \
    case r:           \
        return #r;
        INK_RESULT(VK_SUCCESS)
        INK_RESULT(VK_NOT_READY)
        INK_RESULT(VK_TIMEOUT)
        INK_RESULT(VK_INCOMPLETE)
        INK_RESULT(VK_SUBOPTIMAL_KHR)
        INK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        INK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        INK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        INK_RESULT(VK_ERROR_DEVICE_LOST)
        INK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        INK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        INK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        INK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        INK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        INK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        INK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        INK_RESULT(VK_ERROR_SURFACE_LOST_KHR)
        INK_RESULT(VK_ERROR_OUT_OF_DATE_KHR)
#undef INK_RESULT
        default:
            return "VK_ERROR_(unknown)";
    }
}

// Vulkan failures become ink::Error so that apps exit with one line instead of aborting; the ones a user
// can meet (device lost, out of memory) get a sentence of their own.
void vkFail(const char* call, VkResult result, const char* file, int line) {
    const char* base = std::strrchr(file, '/');
    std::string where = std::string(base ? base + 1 : file) + ":" + std::to_string(line);
    if (result == VK_ERROR_DEVICE_LOST)
        throw Error("the Vulkan device was lost (driver crash or GPU reset) in " + std::string(call) + " at " + where);
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw Error("out of " + std::string(result == VK_ERROR_OUT_OF_DEVICE_MEMORY ? "device" : "host") +
                    " memory in " + call + " at " + where + ": ask for fewer points or a smaller image");
    throw Error(std::string(call) + " failed with " + vkResultName(result) + " at " + where);
}

static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                    VkDebugUtilsMessageTypeFlagsEXT,
                                                    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* ctx = static_cast<Context*>(user);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        if (ctx->validationErrors++ == 0) ctx->firstValidationMessage = data->pMessage;
        if (ctx->validationMessage) ctx->validationMessage(true, data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        ctx->validationWarnings++;
        if (ctx->validationMessage) ctx->validationMessage(false, data->pMessage);
    }
    return VK_FALSE;
}

static bool hasLayer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(), [&](auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

static int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 3;
        default:
            return 4;
    }
}

static std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

static VkInstance createInstance(const ContextOptions& options, bool validation, Context* ctx,
                                 VkDebugUtilsMessengerCreateInfoEXT* messengerInfo) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "inkwell";
    app.pEngineName = "inkwell";
    app.apiVersion = VK_API_VERSION_1_3;

    std::vector<const char*> extensions = options.instanceExtensions;
    std::vector<const char*> layers;
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    if (validation) {
        layers.push_back("VK_LAYER_KHRONOS_validation");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        messengerInfo->sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
        messengerInfo->messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
        messengerInfo->messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        messengerInfo->pfnUserCallback = debugCallback;
        messengerInfo->pUserData = ctx;
        features.pNext = messengerInfo;  // also report on vkCreateInstance/vkDestroyInstance themselves
        info.pNext = &features;
    }
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();

    VkInstance instance = VK_NULL_HANDLE;
    VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_INITIALIZATION_FAILED)
        throw Error("no Vulkan driver found (" + std::string(vkResultName(result)) +
                    "): install mesa-vulkan-drivers for lavapipe, or your GPU's Vulkan driver");
    if (result == VK_ERROR_EXTENSION_NOT_PRESENT)
        throw Error("the Vulkan driver lacks a required instance extension (surface support for the viewer?)");
    VK_CHECK(result);
    return instance;
}

std::vector<std::string> listDevices() {
    ContextOptions options;
    VkInstance instance = createInstance(options, false, nullptr, nullptr);
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    std::vector<std::string> names;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        names.push_back(p.deviceName);
    }
    vkDestroyInstance(instance, nullptr);
    return names;
}

static VkPhysicalDevice pickDevice(VkInstance instance, const std::string& wanted) {
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    if (devices.empty())
        throw Error("no Vulkan device found: install mesa-vulkan-drivers for lavapipe, or your GPU's driver");

    std::vector<VkPhysicalDevice> usable;
    std::string names;
    for (size_t i = 0; i < devices.size(); ++i) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devices[i], &p);
        names += (names.empty() ? "" : ", ") + std::to_string(i) + ": " + p.deviceName;
        if (p.apiVersion >= VK_API_VERSION_1_3) usable.push_back(devices[i]);
    }
    if (usable.empty()) throw Error("no Vulkan 1.3 device found among: " + names);

    if (!wanted.empty()) {
        char* end = nullptr;
        unsigned long index = std::strtoul(wanted.c_str(), &end, 10);
        if (end && *end == '\0') {
            // The index is the one `inkwell devices` lists: every device, usable or not.
            if (index >= devices.size())
                throw Error("--device " + wanted + ": no such device index (devices: " + names + ")");
            if (std::find(usable.begin(), usable.end(), devices[index]) == usable.end()) {
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devices[index], &p);
                throw Error("--device " + wanted + ": " + p.deviceName + " supports Vulkan " +
                            std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." +
                            std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) +
                            ", Inkwell needs 1.3 (devices: " + names + ")");
            }
            return devices[index];
        }
        for (VkPhysicalDevice d : usable) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(d, &p);
            if (lower(p.deviceName).find(lower(wanted)) != std::string::npos) return d;
        }
        throw Error("--device '" + wanted + "' matches no device (devices: " + names + ")");
    }
    std::stable_sort(usable.begin(), usable.end(), [](VkPhysicalDevice x, VkPhysicalDevice y) {
        VkPhysicalDeviceProperties px, py;
        vkGetPhysicalDeviceProperties(x, &px);
        vkGetPhysicalDeviceProperties(y, &py);
        return typeRank(px.deviceType) < typeRank(py.deviceType);
    });
    return usable.front();
}

// Reads what the engine needs to know of ctx.physicalDevice, picks the queue family (unless one is set), and
// refuses a device that lacks what the shaders use.
static void describeDevice(Context& ctx, bool pickQueueFamily = true) {
    VkPhysicalDeviceVulkan11Properties v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
    VkPhysicalDeviceVulkan13Properties v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES, &v11};
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &v13};
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &subgroup};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice, &props2);
    ctx.properties = props2.properties;
    ctx.driverInfo = std::string(driver.driverName) + " " + driver.driverInfo;
    ctx.driverId = driver.driverID;
    ctx.maxBufferSize = std::min(v13.maxBufferSize, v11.maxMemoryAllocationSize);
    ctx.maxSubgroupSize = std::max(v13.maxSubgroupSize, subgroup.subgroupSize);
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice, &ctx.memoryProperties);

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice, &familyCount, families.data());
    if (pickQueueFamily) ctx.queueFamily = UINT32_MAX;
    for (uint32_t i = 0; i < familyCount; ++i)
        if (pickQueueFamily && (families[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
                                   (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
            ctx.queueFamily = i;
            break;
        }
    if (ctx.queueFamily >= familyCount ||
        (families[ctx.queueFamily].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) !=
            (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT))
        throw Error(std::string(ctx.properties.deviceName) + " has no queue for both graphics and compute");

    // The refinement shares the HRBF centres across a subgroup (hrbf.glsl); it and the drawing passes compact
    // lists with ballots.
    const VkSubgroupFeatureFlags subgroupOps = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
                                               VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT |
                                               VK_SUBGROUP_FEATURE_SHUFFLE_BIT;
    if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
        (subgroup.supportedOperations & subgroupOps) != subgroupOps)
        throw Error(std::string(ctx.properties.deviceName) +
                    " lacks subgroup operations in compute shaders (basic, vote, ballot, arithmetic, shuffle), "
                    "which the refinement and drawing need");

    if (ctx.properties.apiVersion < VK_API_VERSION_1_3)
        throw Error(std::string(ctx.properties.deviceName) + " supports Vulkan " +
                    std::to_string(VK_API_VERSION_MAJOR(ctx.properties.apiVersion)) + "." +
                    std::to_string(VK_API_VERSION_MINOR(ctx.properties.apiVersion)) + ", Inkwell needs 1.3");
}

void createContext(Context& ctx, const ContextOptions& options) {
    ctx.validation = options.validation;
    ctx.validationMessage = options.validationMessage;
    if (options.validation && !hasLayer("VK_LAYER_KHRONOS_validation"))
        throw Error(
            "validation was requested but VK_LAYER_KHRONOS_validation is not installed "
            "(apt-get install vulkan-validationlayers)");
    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{};
    ctx.instance = createInstance(options, options.validation, &ctx, &messengerInfo);
    if (options.validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCreateDebugUtilsMessengerEXT"));
        VK_CHECK(create(ctx.instance, &messengerInfo, nullptr, &ctx.messenger));
    }

    ctx.physicalDevice = pickDevice(ctx.instance, options.device);
    describeDevice(ctx);
    VkPhysicalDeviceFeatures supported{};
    vkGetPhysicalDeviceFeatures(ctx.physicalDevice, &supported);
    // Double is optional: only the global fit's evaluation (refine_global.comp) uses it, with its dynamically
    // indexed uniform-block array.
    ctx.float64 = options.float64 && supported.shaderFloat64 && supported.shaderUniformBufferArrayDynamicIndexing;
    // glslang's vulkan1.3 target assumes maintenance4; the refinement needs sync2 and indirect dispatch.
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    v13.synchronization2 = VK_TRUE;
    v13.maintenance4 = VK_TRUE;
    v13.dynamicRendering = VK_TRUE;
    // Of Vulkan 1.2's, bufferDeviceAddress (required of 1.3 devices) for models larger than a storage buffer's
    // range. Query pools are reset on the device (vkCmdResetQueryPool), not with hostQueryReset.
    VkPhysicalDeviceVulkan12Features supported12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &supported12};
    vkGetPhysicalDeviceFeatures2(ctx.physicalDevice, &query);
    ctx.bufferDeviceAddress = supported12.bufferDeviceAddress == VK_TRUE;
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &v13};
    v12.bufferDeviceAddress = ctx.bufferDeviceAddress ? VK_TRUE : VK_FALSE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
    features.features.shaderFloat64 = ctx.float64 ? VK_TRUE : VK_FALSE;
    features.features.shaderUniformBufferArrayDynamicIndexing = ctx.float64 ? VK_TRUE : VK_FALSE;

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = ctx.queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    std::vector<const char*> extensions;
    if (options.presentation) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queueInfo;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkResult result = vkCreateDevice(ctx.physicalDevice, &info, nullptr, &ctx.device);
    if (result == VK_ERROR_FEATURE_NOT_PRESENT || result == VK_ERROR_EXTENSION_NOT_PRESENT)
        throw Error(std::string(ctx.properties.deviceName) + " lacks a feature Inkwell needs (" + vkResultName(result) +
                    ")");
    VK_CHECK(result);
    vkGetDeviceQueue(ctx.device, ctx.queueFamily, 0, &ctx.queue);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = ctx.queueFamily;
    VK_CHECK(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &ctx.commandPool));
}

void adoptContext(Context& ctx, const AdoptedDevice& adopted) {
    if (!adopted.instance || !adopted.physicalDevice || !adopted.device || !adopted.queue)
        throw Error("adopting a Vulkan device needs its instance, physical device, device and queue");
    ctx.ownsDevice = false;
    ctx.instance = adopted.instance;
    ctx.physicalDevice = adopted.physicalDevice;
    ctx.device = adopted.device;
    ctx.queue = adopted.queue;
    ctx.queueFamily = adopted.queueFamily;
    ctx.float64 = adopted.shaderFloat64;
    ctx.bufferDeviceAddress = adopted.bufferDeviceAddress;
    describeDevice(ctx, false);
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = ctx.queueFamily;
    VK_CHECK(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &ctx.commandPool));
}

void destroyContext(Context& ctx) {
    if (!ctx.ownsDevice) {
        // The caller's device and queue stay; only what the engine made on them goes.
        if (ctx.queue) vkQueueWaitIdle(ctx.queue);
        if (ctx.commandPool) vkDestroyCommandPool(ctx.device, ctx.commandPool, nullptr);
        ctx.commandPool = VK_NULL_HANDLE;
        ctx.device = VK_NULL_HANDLE;
        ctx.instance = VK_NULL_HANDLE;
        ctx.queue = VK_NULL_HANDLE;
        return;
    }
    if (ctx.device) {
        vkDeviceWaitIdle(ctx.device);
        vkDestroyCommandPool(ctx.device, ctx.commandPool, nullptr);
        vkDestroyDevice(ctx.device, nullptr);
    }
    if (ctx.messenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(ctx.instance, ctx.messenger, nullptr);
    }
    if (ctx.instance) vkDestroyInstance(ctx.instance, nullptr);
    ctx.device = VK_NULL_HANDLE;
    ctx.messenger = VK_NULL_HANDLE;
    ctx.instance = VK_NULL_HANDLE;
}

VkCommandBuffer beginOneTime(Context& ctx) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = ctx.commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, &cmd));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    return cmd;
}

void endOneTime(Context& ctx, VkCommandBuffer cmd, const std::function<void()>& whileWaiting) {
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    VK_CHECK(vkCreateFence(ctx.device, &fenceInfo, nullptr, &fence));
    VkResult result = vkQueueSubmit2(ctx.queue, 1, &submit, fence);
    if (result == VK_SUCCESS) {
        const uint64_t slice = whileWaiting ? 100'000'000 : UINT64_MAX;  // 100 ms between calls
        while ((result = vkWaitForFences(ctx.device, 1, &fence, VK_TRUE, slice)) == VK_TIMEOUT) whileWaiting();
    }
    vkDestroyFence(ctx.device, fence, nullptr);
    vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &cmd);
    VK_CHECK(result);
}

}  // namespace ink
