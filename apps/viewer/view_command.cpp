// view: the interactive viewer, an application of the public API (include/inkwell/): the window, the device and
// the drawing it opens, and its stats (the viewer itself: viewer.h).
#include "../cli/commands.h"
#include "viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

namespace {

// The first frame also creates pipelines and buffers on some drivers: left out when there are others.
double medianFrameMs(const std::vector<double>& frameMs) {
    if (frameMs.empty()) return 0;
    std::vector<double> v(frameMs.begin() + (frameMs.size() > 1 ? 1 : 0), frameMs.end());
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// glfwInit/glfwTerminate. Without a display this is the one place that says so, before any model work.
struct GlfwLibrary {
    GlfwLibrary() {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        if ((!display || !*display) && (!wayland || !*wayland))
            throw inkwell::Error(
                "cannot open a window: no display (set DISPLAY, or run under xvfb-run); "
                "use 'inkwell render' for headless output");
        if (!glfwInit()) {
            const char* why = nullptr;
            glfwGetError(&why);
            throw inkwell::Error(std::string("cannot open a window: ") + (why ? why : "GLFW failed to start") +
                                 " (run under xvfb-run, or use 'inkwell render' for headless output)");
        }
        if (!glfwVulkanSupported()) {
            glfwTerminate();
            throw inkwell::Error("cannot open a window: GLFW finds no Vulkan loader with surface support");
        }
    }
    ~GlfwLibrary() { glfwTerminate(); }
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;

    static std::vector<const char*> instanceExtensions() {
        uint32_t count = 0;
        const char** names = glfwGetRequiredInstanceExtensions(&count);
        if (!names) throw inkwell::Error("cannot open a window: Vulkan cannot present to this window system");
        return {names, names + count};
    }
};

// Created hidden: it is shown once the model is refined, so that it never sits there blank and unresponsive.
struct Window {
    GLFWwindow* handle = nullptr;
    Window(VkExtent2D size, const std::string& title) {
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        handle = glfwCreateWindow(int(size.width), int(size.height), title.c_str(), nullptr, nullptr);
        if (!handle) {
            const char* why = nullptr;
            glfwGetError(&why);
            throw inkwell::Error(std::string("cannot open a window: ") + (why ? why : "unknown GLFW error"));
        }
    }
    ~Window() { glfwDestroyWindow(handle); }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
};

struct Surface {
    VkInstance instance;
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    Surface(VkInstance i, GLFWwindow* window) : instance(i) {
        VkResult r = glfwCreateWindowSurface(instance, window, nullptr, &surface);
        if (r != VK_SUCCESS)
            throw inkwell::Error("cannot create a Vulkan surface for the window (" + viewer::resultName(r) + ")");
    }
    ~Surface() { vkDestroySurfaceKHR(instance, surface, nullptr); }
    Surface(const Surface&) = delete;
    Surface& operator=(const Surface&) = delete;
};

int runView(Options& o, const ViewOptions& v) {
    finishOptions(o);
    inkwell::checkOutputs({v.screenshot, v.vector, o.statsPath}, {o.model, o.preset});  // before the window opens
    if (!v.vector.empty() && !inkwell::Plot::isVectorPath(v.vector))
        throw inkwell::Error("--vector '" + v.vector + "' is not an .svg or .pdf file");
    VkExtent2D size = kDefaultWindow;
    if (o.command && o.command->count("--size")) size = {o.size[0], o.size[1]};

    GlfwLibrary glfw;
    Window window(size, "inkwell view - " + std::filesystem::path(o.model).filename().string());
    inkwell::Device device = openDevice(o, o.validation, GlfwLibrary::instanceExtensions(), true);
    ViewResult result;
    // With --screenshot or --vector (every save then goes to that one file), they and the stats are renamed into place
    // together once both are written; S-key screenshots to fresh names are saved at once.
    std::optional<inkwell::OutputBatch> outputs;
    if (!v.screenshot.empty() || !v.vector.empty()) outputs.emplace();
    {
        const viewer::Gpu gpu(device);
        Surface surface(gpu.vk.instance, window.handle);
        viewer::checkPresentSupport(gpu, surface.surface);
        const inkwell::Model model = loadModel(o);
        inkwell::Drawing drawing(device, model, o.drawing, reporter());
        // For the drawing's part of the window (the panel takes its right side unless --no-panel); R returns to it.
        const uint32_t width =
            !v.noPanel && size.width > ViewerPanel::kWidth + 16 ? size.width - ViewerPanel::kWidth : size.width;
        resolveView(o, drawing, float(width) / float(size.height));
        glfwShowWindow(window.handle);
        Viewer viewer(o, v, device, gpu, model, drawing, window.handle, surface.surface);
        result = viewer.run();
    }
    checkValidation(device);

    double medianMs = medianFrameMs(result.frameMs);
    json stats = {{"frames", result.frames},      {"panel", result.panel},
                  {"median_frame_ms", medianMs},  {"frame_ms", result.frameMs},
                  {"width", result.extent.width}, {"height", result.extent.height},
                  {"points", result.points},      {"control_points", result.controlPoints}};
    stats.update(deviceJson(device));
    writeJson(o.statsPath, stats);
    if (outputs) outputs->commit();
    std::printf("view: %u frames, median %.2f ms (%ux%u%s, %llu points)\n", result.frames, medianMs,
                result.extent.width, result.extent.height, result.panel ? " with the panel" : "",
                (unsigned long long)result.points);
    return 0;
}

}  // namespace

void addViewCommand(CLI::App& cli, Options& o, Commands& commands) {
    auto v = std::make_shared<ViewOptions>();
    CLI::App* view = cli.add_subcommand("view", "Open a window and view a model interactively (docs/viewer.md)");
    addModelOptions(view, o);
    addRefineOptions(view, o);
    addRenderOptions(view, o);
    addVectorOptions(view, o);  // --vector, the V key and the panel's SVG and PDF
    addDeviceOptions(view, o);
    view->get_option("--size")->description("Window width and height in pixels")->default_str("[1024,768]");
    // The window is drawn at its own resolution every frame; supersampling is for `render`.
    view->remove_option(view->get_option("--supersample"));
    view->add_option("--frames", v->frames, "Quit after this many frames (default: when the window closes)");
    view->add_option("--screenshot", v->screenshot, "Save the last frame (or the S key's) to this PNG");
    view->add_option("--vector", v->vector,
                     "Save the last frame's marks (or the V key's) to this SVG or PDF (page options as render's)");
    view->add_flag("--no-panel", v->noPanel, "Start with the settings panel hidden (Tab shows it)");
    commands.emplace_back(view, [&o, v] { return runView(o, *v); });
}

}  // namespace app
