// view: the interactive viewer, an application of the public API (include/inkwell/). A GLFW window, a FIFO
// swapchain and two frames in flight; every frame an inkwell::FrameRecorder draws straight into the swapchain
// image (no readback unless a screenshot is asked for), and the settings panel (viewer_panel.h) beside it. The
// keys, the mouse and the panel only set state; the frame loop applies it between frames. New refinements run on
// a worker thread (Drawing::prepare), and are put in place between frames (Drawing::apply).
#include "../cli/commands.h"
#include "../cli/preset.h"
#include "viewer_panel.h"
#include "vulkan.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace app {

namespace {

constexpr uint32_t kFramesInFlight = 2;
constexpr VkExtent2D kDefaultWindow{1024, 768};  // fits a 1280×1024 screen with its decorations
constexpr uint32_t kMaxLevels = 8;               // the +/- keys stay in 0..8
constexpr double kTitleInterval = 0.5;           // seconds between window title updates

// Where the L key sends the light, as seen from the default camera (x right, y up, z towards the viewer); it
// stays fixed to the model unless --light-follows-camera.
constexpr std::array<std::array<float, 3>, 5> kLights{{
    {-0.5f, 0.6f, 0.65f},    // upper left: the default
    {0.5f, 0.6f, 0.65f},     // upper right
    {0.0f, 0.0f, 1.0f},      // from the viewer
    {-0.95f, 0.15f, 0.25f},  // raking from the left
    {0.0f, -0.6f, 0.8f},     // from below
}};

struct ViewOptions {
    uint32_t frames = 0;     // 0: until the window closes
    std::string screenshot;  // saved from the last frame
    std::string vector;      // the last frame's marks (or the V key's) as SVG or PDF
    bool noPanel = false;    // start with the panel hidden
};

struct ViewResult {
    uint32_t frames = 0;
    std::vector<double> frameMs;  // from the start of the loop or the previous present to this present
    VkExtent2D extent{};
    uint64_t points = 0;
    size_t controlPoints = 0;
    bool panel = false;  // shown in the last frame
};

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

struct Frame {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;          // created signalled: the first wait returns at once
    VkSemaphore acquired = VK_NULL_HANDLE;  // the swapchain image is ready to be drawn into
};

// The options a change of which needs a new refinement (the panel's and the keys').
bool sameRefinement(const inkwell::DrawingOptions& a, const inkwell::DrawingOptions& b) {
    return a.style == b.style && a.levels == b.levels && a.passes == b.passes && a.direction == b.direction &&
           a.distribution == b.distribution;
}

// The pen-line options a change of which needs the lines traced again (the hatching, or the seeds of both).
bool sameHatching(const inkwell::DrawingOptions& a, const inkwell::DrawingOptions& b) {
    return a.hatching == b.hatching &&
           (!a.hatching || (a.hatchSpacing == b.hatchSpacing && a.hatchFamilies == b.hatchFamilies));
}
bool sameLines(const inkwell::DrawingOptions& a, const inkwell::DrawingOptions& b) {
    return a.contours == b.contours && a.creases == b.creases && a.boundaries == b.boundaries && sameHatching(a, b);
}
bool anyLines(const inkwell::DrawingOptions& o) { return o.contours || o.hatching || o.creases || o.boundaries; }

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A new refinement, or new pen lines over the current one, made on a worker thread while the window keeps
// handling events (Drawing::prepare). The frames stop meanwhile: the device runs one queue in order, so a frame
// submitted after the refinement would wait for it anyway, and the worker has the queue to itself.
struct RefineJob {
    bool refine = true;  // new point sets; else only the pen lines of the current ones
    inkwell::DrawingOptions options;
    std::thread thread;
    std::atomic<bool> finished{false}, tracing{false};
    std::atomic<uint32_t> permille{0};
    inkwell::Drawing::Pending pending;  // the rest is written by the worker before `finished`, read after
    std::string error;
    std::vector<std::string> notes;
};

class Viewer {
public:
    Viewer(Options& o, const ViewOptions& v, inkwell::Device& device, const viewer::Gpu& gpu,
           const inkwell::Model& model, inkwell::Drawing& drawing, GLFWwindow* window, VkSurfaceKHR surface);
    ~Viewer() { release(); }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    ViewResult run();

    // GLFW callbacks: they only record what to do, the loop does it (no Vulkan work, nothing that throws). The
    // panel gets every event first; what it takes (typing in a field, a click on it) the viewer leaves alone.
    void onKey(int key, int scancode, int action, int mods);
    void onChar(unsigned int c);
    void onMouseButton(int button, int action, int mods);
    void onCursor(double x, double y);
    void onScroll(double dx, double dy);
    void onResize() { resized_ = true; }

private:
    bool ensureSwapchain();
    bool drawFrame(const std::string& screenshot);
    void record(Frame& f, uint32_t image, bool capture);
    void submitAndPresent(Frame& f, uint32_t image, bool suboptimal);
    void saveCapture(Frame& f, const std::string& path);
    VkExtent2D drawingExtent() const;
    bool panelDrawn() const;
    void buildPanel(double frameMs);
    // Whether the options ask for other point sets or pen lines than those drawn.
    bool stale() const { return !sameRefinement(o_.drawing, applied_) || !sameLines(o_.drawing, applied_); }
    void startRefinement();
    void finishRefinement();
    void copyCamera();
    void pasteCamera();
    void savePng(const std::string& path, uint32_t width, uint32_t height);
    void say(const std::string& line, bool error);
    void updateTitle(double averageMs);
    std::string nextScreenshotPath();
    std::string nextDrawingPath() const;
    void saveVector();  // the marks of the frame drawn last, to --vector or the next free inkwell-view-N.svg
    bool quitting() const { return quit_ || glfwWindowShouldClose(window_); }
    void release();

    Options& o_;
    ViewOptions v_;
    inkwell::Device& device_;
    const viewer::Gpu& gpu_;
    inkwell::Drawing& drawing_;
    size_t controlPoints_;
    GLFWwindow* window_;
    VkSurfaceKHR surface_;
    VkSurfaceFormatKHR format_{};
    viewer::Swapchain swapchain_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::array<Frame, kFramesInFlight> frames_{};
    uint32_t current_ = 0;
    std::unique_ptr<inkwell::FrameRecorder> recorder_;
    uint64_t points_ = 0;

    std::unique_ptr<ViewerPanel> panel_;
    std::unique_ptr<RefineJob> job_;
    std::string message_;     // the panel's last line: what was saved, loaded or refused
    std::string pngDefault_;  // the panel's PNG file to begin with

    inkwell::Camera camera_, home_;
    std::optional<inkwell::Camera> autoHome_;  // the first picture of `--up auto`, for the panel's "auto" up entry
    std::array<float, 3> previousEye_{kNaN, kNaN, kNaN};  // the last frame's eye
    bool traced_ = false;                                 // a contour was traced (its time is known)
    inkwell::DrawingOptions applied_;                     // of the sets and lines drawn
    float toneGamma_;                                     // what T restores
    size_t light_ = 0;
    double lastX_ = 0, lastY_ = 0;
    bool resized_ = false, quit_ = false, restyle_ = true, rerefine_ = false, screenshotKey_ = false;
    bool vectorKey_ = false;
    bool dragging_ = false;  // a drag that began on the drawing (not on the panel) moves the camera
};

Viewer& viewerOf(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

Viewer::Viewer(Options& o, const ViewOptions& v, inkwell::Device& device, const viewer::Gpu& gpu,
               const inkwell::Model& model, inkwell::Drawing& drawing, GLFWwindow* window, VkSurfaceKHR surface)
    : o_(o),
      v_(v),
      device_(device),
      gpu_(gpu),
      drawing_(drawing),
      controlPoints_(model.report().controlPoints),
      window_(window),
      surface_(surface),
      camera_(cameraFrom(o)),
      home_(camera_),
      autoHome_(o.autoUp && o.autoView ? std::optional<inkwell::Camera>(camera_) : std::nullopt),
      applied_(o.drawing),
      toneGamma_(o.look.toneGamma > 0 ? o.look.toneGamma : 1.5f) {
    const VkDevice vk = gpu.vk.device;
    try {
        std::string warning;
        format_ = viewer::chooseSurfaceFormat(gpu, surface, warning);
        if (!warning.empty()) note(warning);
        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = gpu.vk.queueFamily;
        VIEWER_CHECK(vkCreateCommandPool(vk, &poolInfo, nullptr, &pool_));
        for (Frame& f : frames_) {
            VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            alloc.commandPool = pool_;
            alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            alloc.commandBufferCount = 1;
            VIEWER_CHECK(vkAllocateCommandBuffers(vk, &alloc, &f.cmd));
            VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
            fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
            VIEWER_CHECK(vkCreateFence(vk, &fenceInfo, nullptr, &f.done));
            VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
            VIEWER_CHECK(vkCreateSemaphore(vk, &semaphoreInfo, nullptr, &f.acquired));
        }
        recorder_ = std::make_unique<inkwell::FrameRecorder>(drawing, format_.format, kFramesInFlight, o.look);
        points_ = drawing.pointCount();
        panel_ = std::make_unique<ViewerPanel>(gpu, window, format_.format, kFramesInFlight);
        if (v.noPanel) panel_->toggle();
    } catch (...) {
        release();
        throw;
    }
    glfwSetWindowUserPointer(window, this);
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
        viewerOf(w).onKey(key, scancode, action, mods);
    });
    glfwSetCharCallback(window, [](GLFWwindow* w, unsigned int c) { viewerOf(w).onChar(c); });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
        viewerOf(w).onMouseButton(button, action, mods);
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) { viewerOf(w).onCursor(x, y); });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) { viewerOf(w).onScroll(dx, dy); });
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) { viewerOf(w).onResize(); });
    glfwSetCursorEnterCallback(window, [](GLFWwindow* w, int entered) {
        viewerOf(w).panel_->inputArrived();
        ImGui_ImplGlfw_CursorEnterCallback(w, entered);
    });
    glfwSetWindowFocusCallback(window, [](GLFWwindow* w, int focused) {
        viewerOf(w).panel_->inputArrived();
        ImGui_ImplGlfw_WindowFocusCallback(w, focused);
    });
    glfwGetCursorPos(window, &lastX_, &lastY_);
}

// Reverse order of creation; safe on a partly constructed viewer.
void Viewer::release() {
    if (job_) {  // a refinement cannot be stopped on the device: wait for it
        job_->thread.join();
        job_.reset();
    }
    glfwSetKeyCallback(window_, nullptr);
    glfwSetCharCallback(window_, nullptr);
    glfwSetMouseButtonCallback(window_, nullptr);
    glfwSetCursorPosCallback(window_, nullptr);
    glfwSetScrollCallback(window_, nullptr);
    glfwSetFramebufferSizeCallback(window_, nullptr);
    glfwSetCursorEnterCallback(window_, nullptr);
    glfwSetWindowFocusCallback(window_, nullptr);
    glfwSetWindowUserPointer(window_, nullptr);
    vkDeviceWaitIdle(gpu_.vk.device);
    panel_.reset();
    recorder_.reset();
    for (Frame& f : frames_) {
        vkDestroySemaphore(gpu_.vk.device, f.acquired, nullptr);
        vkDestroyFence(gpu_.vk.device, f.done, nullptr);
        f = Frame{};
    }
    vkDestroyCommandPool(gpu_.vk.device, pool_, nullptr);  // frees the command buffers
    pool_ = VK_NULL_HANDLE;
    viewer::destroySwapchain(gpu_, swapchain_);
}

void Viewer::onKey(int key, int scancode, int action, int mods) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_KeyCallback(window_, key, scancode, action, mods);
        if (panel_->wantsKeyboard()) return;  // typing into one of its fields
    }
    bool press = action == GLFW_PRESS, repeat = action == GLFW_REPEAT;
    if (!press && !(repeat && (key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET))) return;
    inkwell::Look& s = o_.look;
    switch (key) {
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q:
            quit_ = true;
            break;
        case GLFW_KEY_1:
            o_.drawing.style = inkwell::Style::Stipple;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_2:
            o_.drawing.style = inkwell::Style::Direction;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_3:
            o_.drawing.style = inkwell::Style::Both;
            s.dots = true;
            restyle_ = true;
            break;
        case GLFW_KEY_EQUAL:  // '+' is shift+'=' on most layouts; '=' alone counts too
        case GLFW_KEY_KP_ADD:
            o_.drawing.levels = std::min(o_.drawing.levels + 1, kMaxLevels);
            break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT:
            o_.drawing.levels = o_.drawing.levels > 0 ? o_.drawing.levels - 1 : 0;
            break;
        case GLFW_KEY_LEFT_BRACKET:
            s.tau = std::max(0.0f, s.tau - 0.02f);
            restyle_ = true;
            break;
        case GLFW_KEY_RIGHT_BRACKET:
            s.tau = std::min(0.9f, s.tau + 0.02f);
            restyle_ = true;
            break;
        case GLFW_KEY_T:
            if (s.toneGamma > 0) {
                toneGamma_ = s.toneGamma;
                s.toneGamma = 0;  // every front dot
            } else {
                s.toneGamma = toneGamma_;
            }
            restyle_ = true;
            break;
        case GLFW_KEY_H:
            s.hiddenLines = !s.hiddenLines;
            restyle_ = true;
            break;
        case GLFW_KEY_O:
            s.occlusion = !s.occlusion;
            restyle_ = true;
            break;
        case GLFW_KEY_L:
            light_ = (light_ + 1) % kLights.size();
            s.light = kLights[light_];
            restyle_ = true;
            break;
        case GLFW_KEY_U:  // the next up axis: y, z, x, -y, -z, -x (a z-up scan stands up in one press)
        {
            // With `--up auto` at the start, "auto" takes the place of the axis it found: the cycle goes on from
            // it to the next axis, and back to it (and to its first picture) where that axis would come.
            static constexpr inkwell::Up kOrder[] = {inkwell::Up::Y,    inkwell::Up::Z,    inkwell::Up::X,
                                                     inkwell::Up::NegY, inkwell::Up::NegZ, inkwell::Up::NegX};
            size_t k = 0;
            while (kOrder[k] != o_.up) ++k;
            const inkwell::Up next = kOrder[(k + 1) % 6];
            if (autoHome_ && !o_.autoUp && next == autoHome_->up) {
                o_.up = next;
                camera_ = home_ = *autoHome_;
                o_.autoUp = true;
            } else {
                o_.up = next;
                camera_.up = home_.up = o_.up;
                o_.autoUp = false;  // chosen: a saved preset keeps it
            }
            restyle_ = true;  // the light is fixed to the model as seen from the default camera of this axis
            break;
        }
        case GLFW_KEY_S:
            screenshotKey_ = true;
            break;
        case GLFW_KEY_C:  // ctrl + C, ctrl + V: the camera as text on the clipboard (docs/viewer.md)
            if (mods & GLFW_MOD_CONTROL) copyCamera();
            break;
        case GLFW_KEY_V:
            if (mods & GLFW_MOD_CONTROL)
                pasteCamera();
            else
                vectorKey_ = true;
            break;
        case GLFW_KEY_R:
            camera_ = home_;
            break;
        case GLFW_KEY_TAB:
            if (panel_) panel_->toggle();
            break;
        case GLFW_KEY_F1:
            if (panel_) panel_->showHelp();
            break;
        default:
            break;
    }
    if (stale()) rerefine_ = true;
}

void Viewer::onChar(unsigned int c) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_CharCallback(window_, c);
    }
}

void Viewer::onMouseButton(int button, int action, int mods) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_MouseButtonCallback(window_, button, action, mods);
    }
    if (action == GLFW_PRESS) dragging_ = !(panel_ && panel_->wantsMouse());
}

void Viewer::onCursor(double x, double y) {
    double dx = x - lastX_, dy = y - lastY_;
    lastX_ = x;
    lastY_ = y;
    if (panel_) panel_->inputArrived();  // hovering changes it
    if (!dragging_) return;
    bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                 glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    if (right || (left && shift)) {
        camera_.pan(dx, dy, swapchain_.extent.height);
    } else if (left) {
        // Grab-and-turn: dragging right turns the model right, i.e. the camera goes left around it.
        camera_.azimuthDeg = std::fmod(camera_.azimuthDeg - float(dx) * 0.3f, 360.0f);
        camera_.elevationDeg += float(dy) * 0.3f;
        camera_.elevationDeg = camera_.freeOrbit ? std::remainder(camera_.elevationDeg, 360.0f)
                                                 : std::clamp(camera_.elevationDeg, -89.0f, 89.0f);
    }
}

void Viewer::onScroll(double dx, double dy) {
    if (panel_) {
        panel_->inputArrived();
        ImGui_ImplGlfw_ScrollCallback(window_, dx, dy);
        if (panel_->wantsMouse()) return;  // scrolls the panel
    }
    camera_.distance = std::clamp(camera_.distance * float(std::pow(0.9, dy)), 0.1f, 50.0f);
}

// (Re)creates the swapchain when there is none or the window changed; false while the window has no area.
bool Viewer::ensureSwapchain() {
    if (swapchain_.swapchain && !resized_) return true;
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    if (!viewer::createSwapchain(gpu_, swapchain_, surface_, format_, {uint32_t(width), uint32_t(height)}))
        return false;
    resized_ = false;
    if (panel_) panel_->swapchainChanged();
    if (!v_.screenshot.empty() && !swapchain_.copyable)
        throw inkwell::Error("this window system's images cannot be copied, so --screenshot cannot work");
    return true;
}

// Starts a new refinement for the style and refinement options asked for, or new pen lines over the current
// one, on a worker thread. Lines switched on or off over lines already traced need no tracing: at once.
void Viewer::startRefinement() {
    rerefine_ = false;
    const bool refine = !sameRefinement(o_.drawing, applied_);
    if (!refine && sameHatching(o_.drawing, applied_) && (anyLines(applied_) || !anyLines(o_.drawing))) {
        drawing_.apply(drawing_.prepare(o_.drawing, reporter()));  // nothing to make or trace
        applied_ = o_.drawing;
        restyle_ = true;
        say(std::string("contours ") + (o_.drawing.contours ? "on" : "off"), false);
        return;
    }
    job_ = std::make_unique<RefineJob>();
    RefineJob* job = job_.get();
    job->refine = refine;
    job->options = o_.drawing;
    job->tracing = !refine;
    job->thread = std::thread([this, job] {
        const size_t sets = job->options.style == inkwell::Style::Both ? 2 : 1;
        size_t setsDone = 0;
        inkwell::Reporter progress;
        progress.progress = [&](const char*, size_t done, size_t total) {
            job->permille =
                uint32_t(1000 * (double(setsDone) + double(done) / double(std::max<size_t>(total, 1))) / double(sets));
            if (done >= total) setsDone = std::min(setsDone + 1, sets);
            if (setsDone == sets) job->tracing = true;  // the sets are made: the lines next
        };
        progress.note = [job](const std::string& line) { job->notes.push_back(line); };
        try {
            job->pending = drawing_.prepare(job->options, progress);
        } catch (const std::exception& e) {
            job->error = e.what();
        }
        job->finished = true;
        glfwPostEmptyEvent();  // wakes the loop if it waits for events
    });
}

// Puts the finished refinement or lines in place (or, if it failed, says why and keeps the drawing as it was).
// The recorder draws the new sets and lines from its next frame.
void Viewer::finishRefinement() {
    job_->thread.join();
    std::unique_ptr<RefineJob> job = std::move(job_);
    for (const std::string& line : job->notes) note(line);
    if (!job->error.empty()) {
        // Too many points for this device, say: keep viewing what was there.
        o_.drawing = applied_;
        say(job->error + "; keeping " + styleName(o_) + " at " + std::to_string(applied_.levels) + " levels", true);
        return;
    }
    const bool refined = job->pending.refined(), traced = job->pending.traced();
    const double seconds = job->pending.seconds(), traceSeconds = job->pending.traceSeconds();
    const size_t strokes = job->pending.hatchStrokes();
    drawing_.apply(std::move(job->pending));
    applied_ = job->options;
    restyle_ = true;
    std::string message;
    if (refined) {
        points_ = drawing_.pointCount();
        char line[160];
        std::snprintf(line, sizeof line, "refined %s at %u levels in %.2f s: %llu points",
                      inkwell::styleName(applied_.style), applied_.levels, seconds, (unsigned long long)points_);
        message = line;
    }
    if (traced && applied_.hatching) {
        char line[120];
        std::snprintf(line, sizeof line, "%shatching traced in %.2f s: %zu strokes", message.empty() ? "" : "; ",
                      traceSeconds, strokes);
        message += line;
    } else if (!refined) {
        message = std::string("pen lines: ") + (applied_.contours ? "contours" : "none");
    }
    say(message, false);
    // Changed again while it ran: once more.
    if (stale()) rerefine_ = true;
}

// The camera as one line of JSON on the clipboard (parseCameraText reads it, and `--camera` options, back).
void Viewer::copyCamera() {
    CameraText c;
    c.azimuthDeg = camera_.azimuthDeg;
    c.elevationDeg = camera_.elevationDeg;
    c.distance = camera_.distance;
    c.target = camera_.target;
    c.up = inkwell::upName(o_.up);
    c.fovDeg = camera_.fovyDeg;
    c.freeOrbit = camera_.freeOrbit;
    const std::string text = cameraJson(c);
    glfwSetClipboardString(window_, text.c_str());
    say("copied the camera " + text, false);
}

// The clipboard's camera, if it holds one; else the panel says why and the camera stays.
void Viewer::pasteCamera() {
    const char* clipboard = glfwGetClipboardString(window_);
    try {
        if (!clipboard) throw inkwell::Error("the clipboard holds no text");
        const CameraText c = parseCameraText(clipboard);
        if (c.up) {
            o_.up = inkwell::parseUp(*c.up);
            home_.up = o_.up;
            o_.autoUp = false;
            restyle_ = true;  // the light is given about the up axis
        }
        camera_.up = o_.up;
        if (c.freeOrbit) camera_.freeOrbit = *c.freeOrbit;
        camera_.azimuthDeg = c.azimuthDeg;
        camera_.elevationDeg = camera_.freeOrbit ? c.elevationDeg : std::clamp(c.elevationDeg, -89.0f, 89.0f);
        camera_.distance = std::clamp(c.distance, 0.1f, 50.0f);
        if (c.target) camera_.target = *c.target;
        if (c.fovDeg) camera_.fovyDeg = std::clamp(*c.fovDeg, 10.0f, 100.0f);
        say("pasted the camera", false);
    } catch (const inkwell::Error& e) {
        say(std::string("camera not pasted: ") + e.what(), true);
    }
}

// The panel's notes go to its last line and, as the viewer's other notes, to the terminal.
void Viewer::say(const std::string& line, bool error) {
    message_ = line;
    if (error)
        note(line);
    else
        std::printf("view: %s\n", line.c_str());
    std::fflush(stdout);
}

VkExtent2D Viewer::drawingExtent() const {
    VkExtent2D e = swapchain_.extent;
    if (panel_) e.width = panel_->drawingWidth(e.width);
    return e;
}

bool Viewer::panelDrawn() const { return panel_ && drawingExtent().width < swapchain_.extent.width; }

// The panel's widgets for this frame, and what they asked for.
void Viewer::buildPanel(double frameMs) {
    PanelInfo info;
    info.model = std::filesystem::path(o_.model).filename().string();
    info.controlPoints = controlPoints_;
    info.points = points_;
    info.frameMs = frameMs;
    info.refining = rerefine_ || job_;
    info.refineProgress = job_ ? job_->permille / 1000.0 : 0.0;
    info.task = job_ && job_->tracing ? "tracing the lines" : "refining";
    info.message = message_;
    info.screenshotPath = v_.screenshot.empty() ? "inkwell-view-N.png (the first free N)" : v_.screenshot;
    info.drawing = drawingExtent();
    info.autoUp = autoHome_ ? inkwell::upName(autoHome_->up) : nullptr;
    if (pngDefault_.empty()) pngDefault_ = nextDrawingPath();
    info.pngPath = pngDefault_;
    PanelActions a = panel_->build(o_, camera_, info);
    if (a.restyle) restyle_ = true;
    if (a.rerefine) rerefine_ = true;
    if (a.upChanged) {
        camera_.up = home_.up = o_.up;
        o_.autoUp = false;
    }
    if (a.upAuto && autoHome_) {
        o_.up = autoHome_->up;
        camera_ = home_ = *autoHome_;
        o_.autoUp = true;
    }
    if (a.resetCamera) camera_ = home_;
    if (a.copyCamera) copyCamera();
    if (a.pasteCamera) pasteCamera();
    if (a.saveScreenshot) screenshotKey_ = true;
    if (a.savePng && !job_) {
        try {
            savePng(a.pngPath, a.pngSize[0], a.pngSize[1]);
            say("saved " + a.pngPath, false);
        } catch (const inkwell::Error& e) {
            say(std::string("not saved: ") + e.what(), true);
        }
    }
    if (a.savePreset) {
        try {
            inkwell::checkOutputs({a.presetPath}, {o_.model});
            inkwell::OutputBatch now;  // at once, even inside the --screenshot batch
            inkwell::writeFileAtomically(a.presetPath, presetJson(presetFrom(o_)));
            now.commit();
            say("saved preset " + a.presetPath, false);
        } catch (const inkwell::Error& e) {
            say(std::string("preset not saved: ") + e.what(), true);
        }
    }
    if (a.loadPreset) {
        try {
            loadPreset(o_, a.presetPath);
            camera_.up = home_.up = o_.up;
            restyle_ = true;
            if (stale()) rerefine_ = true;
            say("loaded preset " + a.presetPath, false);
        } catch (const inkwell::Error& e) {
            say(e.what(), true);
        }
    }
}

// What `inkwell render -o path` draws with the same options and camera at width × height: a PNG supersampled as
// it does, or (.svg, .pdf) the frame's marks laid out on the page of the --page options.
void Viewer::savePng(const std::string& path, uint32_t width, uint32_t height) {
    inkwell::checkOutputs({path}, {o_.model, o_.preset});
    device_.checkImageSize(width, height, o_.look.supersample);
    inkwell::Renderer offscreen(drawing_, width, height, o_.look);
    const inkwell::Image image = offscreen.render(camera_);  // the pen lines of this view, as render's
    inkwell::OutputBatch now;                                // at once, even inside the --screenshot batch
    if (inkwell::Plot::isVectorPath(path))
        offscreen.plot(o_.page).write(path);
    else
        image.writePng(path);
    now.commit();
}

void Viewer::record(Frame& f, uint32_t index, bool capture) {
    // The contour depends on the eye: traced again every frame while a trace takes under kTraceBudget (the device's
    // tracer on a GPU, a few milliseconds), else once the eye stops (a frame without motion; the CPU tracer on
    // lavapipe takes 35–45 ms for the bunny), the last view's contour drawn while it moves (docs/lines.md).
    constexpr double kTraceBudget = 0.008;
    const std::array<float, 3> eye = camera_.eye();
    const bool moving = eye != previousEye_;
    const bool trace = !moving || (traced_ && drawing_.contourSeconds() < kTraceBudget);
    traced_ |= trace && applied_.contours;
    previousEye_ = eye;
    VkCommandBuffer cmd = f.cmd;
    VIEWER_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VIEWER_CHECK(vkBeginCommandBuffer(cmd, &begin));
    if (restyle_) {
        recorder_->setLook(o_.look);
        restyle_ = false;
    }
    // The acquire semaphore is waited on at colour output: the image's transition comes after that stage. The
    // drawing takes the window's left part; the panel, drawn after it (and after a screenshot's copy), the rest.
    const bool panel = panelDrawn();
    inkwell::FrameTarget target{
        swapchain_.images[index],
        swapchain_.views[index],
        drawingExtent(),
        panel ? panel_->layoutBefore(swapchain_, drawingExtent().width) : VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
        capture};
    recorder_->record(cmd, camera_, target, current_, trace);
    if (panel) panel_->record(cmd, swapchain_, index, target.extent.width);
    VIEWER_CHECK(vkEndCommandBuffer(cmd));
}

void Viewer::submitAndPresent(Frame& f, uint32_t index, bool suboptimal) {
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = f.acquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = swapchain_.rendered[index];
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = f.cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    VIEWER_CHECK(vkQueueSubmit2(gpu_.vk.queue, 1, &submit, f.done));

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &swapchain_.rendered[index];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_.swapchain;
    present.pImageIndices = &index;
    VkResult presented = vkQueuePresentKHR(gpu_.vk.queue, &present);
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || suboptimal)
        resized_ = true;  // recreated before the next frame
    else
        VIEWER_CHECK(presented);
}

// Draws and presents one frame, saving it to `screenshot` when that is not empty. False when the
// swapchain was out of date and nothing was drawn (it is recreated before the next try).
bool Viewer::drawFrame(const std::string& screenshot) {
    Frame& f = frames_[current_];
    VIEWER_CHECK(vkWaitForFences(gpu_.vk.device, 1, &f.done, VK_TRUE, UINT64_MAX));
    uint32_t index = 0;
    VkResult acquired =
        vkAcquireNextImageKHR(gpu_.vk.device, swapchain_.swapchain, UINT64_MAX, f.acquired, VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        resized_ = true;
        return false;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) VIEWER_CHECK(acquired);
    // Only now: a frame that returned above must leave the fence signalled for the next wait.
    VIEWER_CHECK(vkResetFences(gpu_.vk.device, 1, &f.done));

    const bool capture = !screenshot.empty();
    record(f, index, capture);
    submitAndPresent(f, index, acquired == VK_SUBOPTIMAL_KHR);
    if (capture) saveCapture(f, screenshot);
    current_ = (current_ + 1) % kFramesInFlight;
    return true;
}

void Viewer::saveCapture(Frame& f, const std::string& path) {
    VIEWER_CHECK(vkWaitForFences(gpu_.vk.device, 1, &f.done, VK_TRUE, UINT64_MAX));
    recorder_->captured(current_).writePng(path);  // the drawing, at the extent the frame was recorded with
}

std::string Viewer::nextScreenshotPath() {
    if (!v_.screenshot.empty()) return v_.screenshot;
    for (uint32_t n = 1;; ++n) {
        std::string path = "inkwell-view-" + std::to_string(n) + ".png";
        if (!std::filesystem::exists(path)) return path;
    }
}

void Viewer::saveVector() {
    std::string path = v_.vector;
    for (uint32_t n = 1; path.empty(); ++n) {
        std::string name = "inkwell-view-" + std::to_string(n) + ".svg";
        if (!std::filesystem::exists(name)) path = name;
    }
    uint32_t frame = (current_ + kFramesInFlight - 1) % kFramesInFlight;  // drawFrame moved on past it
    recorder_->plot(frame, o_.page).write(path);
    std::printf("view: saved %s\n", path.c_str());
    std::fflush(stdout);  // scripts wait for it
}

std::string Viewer::nextDrawingPath() const {
    for (uint32_t n = 1;; ++n) {
        std::string path = "inkwell-drawing-" + std::to_string(n) + ".png";
        if (!std::filesystem::exists(path)) return path;
    }
}

void Viewer::updateTitle(double averageMs) {
    char title[256];
    std::snprintf(title, sizeof(title), "inkwell view - %s - %s, %u levels - %llu points - %.1f ms",
                  std::filesystem::path(o_.model).filename().c_str(), styleName(o_).c_str(), o_.drawing.levels,
                  (unsigned long long)points_, averageMs);
    glfwSetWindowTitle(window_, title);
}

ViewResult Viewer::run() {
    ViewResult result;
    auto previous = Clock::now(), titleStart = previous;
    double titleMs = 0, averageMs = 0;
    uint32_t titleFrames = 0;
    bool savedLast = false, savedVectorLast = false;
    while (!quitting() || job_) {
        if (job_) {
            // A refinement runs: keep handling events (and show its progress in the title) until it is done.
            if (!job_->finished) {
                glfwWaitEventsTimeout(0.1);
                char title[256];
                if (job_->tracing)
                    std::snprintf(title, sizeof title, "inkwell view - %s - tracing the lines",
                                  std::filesystem::path(o_.model).filename().c_str());
                else
                    std::snprintf(title, sizeof title, "inkwell view - %s - refining %d%%",
                                  std::filesystem::path(o_.model).filename().c_str(), int(job_->permille / 10));
                glfwSetWindowTitle(window_, title);
                continue;
            }
            finishRefinement();
            updateTitle(averageMs);
            previous = Clock::now();  // the refinement is not a frame
            if (quitting()) break;
        }
        glfwPollEvents();
        if (glfwGetWindowAttrib(window_, GLFW_ICONIFIED) || !ensureSwapchain()) {
            glfwWaitEvents();  // minimized: nothing to draw until the window is back
            previous = Clock::now();
            continue;
        }
        // The panel first: what it changes shows in this frame. A change that needs a new refinement is drawn
        // once with the panel saying so, then refined.
        if (panelDrawn()) buildPanel(averageMs);
        result.panel = panelDrawn();
        bool last = v_.frames > 0 && result.frames + 1 == v_.frames;
        std::string screenshot;
        if (screenshotKey_ || (last && !v_.screenshot.empty())) screenshot = nextScreenshotPath();
        bool fromKey = screenshotKey_;
        bool drawn = false;
        try {
            drawn = drawFrame(screenshot);
        } catch (const inkwell::Error& e) {
            if (!fromKey) throw;
            note(std::string("screenshot not saved: ") + e.what());  // an S key failure keeps the view
            screenshotKey_ = false;
            continue;
        }
        if (!drawn) {
            if (rerefine_) startRefinement();
            continue;
        }
        if (!screenshot.empty()) {
            std::printf("view: saved %s\n", screenshot.c_str());
            std::fflush(stdout);  // scripts wait for it
            screenshotKey_ = false;
            savedLast = last;
        }
        if (vectorKey_ || (last && !v_.vector.empty())) {
            try {
                saveVector();
                savedVectorLast = last;
            } catch (const inkwell::Error& e) {
                if (!vectorKey_) throw;
                note(std::string("drawing not saved: ") + e.what());  // a V key failure keeps the view
            }
            vectorKey_ = false;
        }
        auto now = Clock::now();
        double ms = std::chrono::duration<double, std::milli>(now - previous).count();
        previous = now;
        result.frameMs.push_back(ms);
        ++result.frames;
        titleMs += ms;
        ++titleFrames;
        if (std::chrono::duration<double>(now - titleStart).count() >= kTitleInterval) {
            averageMs = titleMs / titleFrames;
            updateTitle(averageMs);
            titleStart = now;
            titleMs = 0;
            titleFrames = 0;
        }
        if (v_.frames > 0 && result.frames >= v_.frames) break;
        if (rerefine_) startRefinement();
    }
    // Closed or quit before a --screenshot was taken: draw one more frame for it.
    for (int attempt = 0; !v_.screenshot.empty() && !savedLast && attempt < 3; ++attempt)
        if (ensureSwapchain() && drawFrame(v_.screenshot)) {
            std::printf("view: saved %s\n", v_.screenshot.c_str());
            savedLast = true;
        }
    if (!v_.screenshot.empty() && !savedLast) note("no frame to save to " + v_.screenshot + " (minimized?)");
    if (!v_.vector.empty() && !savedVectorLast) {
        if (result.frames > 0)
            saveVector();  // closed before the last frame: the frame drawn last
        else
            note("no frame to save to " + v_.vector + " (minimized?)");
    }
    VIEWER_CHECK(vkDeviceWaitIdle(gpu_.vk.device));
    result.extent = swapchain_.extent;
    result.points = points_;
    result.controlPoints = controlPoints_;
    return result;
}

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
