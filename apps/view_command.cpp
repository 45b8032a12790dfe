// view: the interactive viewer. A GLFW window, a FIFO swapchain and two frames in flight; every frame the
// same PointRenderer as `render` draws straight into the swapchain image (no readback unless a screenshot
// is asked for). The keys and the mouse only set state; the frame loop applies it between frames.
#include "commands.h"
#include "files.h"
#include "image.h"
#include "swapchain.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app {

namespace {

constexpr uint32_t kFramesInFlight = 2;
constexpr VkExtent2D kDefaultWindow{1024, 768};  // fits a 1280×1024 screen with its decorations
constexpr uint32_t kMaxLevels = 8;               // the +/- keys stay in 0..8
constexpr double kTitleInterval = 0.5;           // seconds between window title updates

// Where the L key sends the light, as seen from the default camera (x right, y up, z towards the viewer); it
// stays fixed to the model unless --light-follows-camera.
constexpr std::array<glm::vec3, 5> kLights{{
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
};

struct ViewResult {
    uint32_t frames = 0;
    std::vector<double> frameMs;  // from the start of the loop or the previous present to this present
    VkExtent2D extent{};
    uint64_t points = 0;
    size_t controlPoints = 0;
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
            throw ink::Error(
                "cannot open a window: no display (set DISPLAY, or run under xvfb-run); "
                "use 'inkwell render' for headless output");
        if (!glfwInit()) {
            const char* why = nullptr;
            glfwGetError(&why);
            throw ink::Error(std::string("cannot open a window: ") + (why ? why : "GLFW failed to start") +
                             " (run under xvfb-run, or use 'inkwell render' for headless output)");
        }
        if (!glfwVulkanSupported()) {
            glfwTerminate();
            throw ink::Error("cannot open a window: GLFW finds no Vulkan loader with surface support");
        }
    }
    ~GlfwLibrary() { glfwTerminate(); }
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;

    static std::vector<const char*> instanceExtensions() {
        uint32_t count = 0;
        const char** names = glfwGetRequiredInstanceExtensions(&count);
        if (!names) throw ink::Error("cannot open a window: Vulkan cannot present to this window system");
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
            throw ink::Error(std::string("cannot open a window: ") + (why ? why : "unknown GLFW error"));
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
            throw ink::Error(std::string("cannot create a Vulkan surface for the window (") + ink::vkResultName(r) +
                             ")");
    }
    ~Surface() { vkDestroySurfaceKHR(instance, surface, nullptr); }
    Surface(const Surface&) = delete;
    Surface& operator=(const Surface&) = delete;
};

struct Frame {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;          // created signalled: the first wait returns at once
    VkSemaphore acquired = VK_NULL_HANDLE;  // the swapchain image is ready to be drawn into
    ink::Buffer capture;                    // only while this frame takes a screenshot
};

// Moves the camera target in the view plane by a mouse movement in pixels: the point under the cursor
// follows it at the target's depth.
void pan(ink::Camera& c, double dx, double dy, uint32_t height) {
    glm::mat4 view = c.view();
    glm::vec3 right(view[0][0], view[1][0], view[2][0]);
    glm::vec3 up(view[0][1], view[1][1], view[2][1]);
    float viewHeight = 2.0f * c.distance * std::tan(glm::radians(c.fovyDeg) * 0.5f);
    float perPixel = viewHeight / float(std::max(1u, height));
    c.target += (-float(dx) * right + float(dy) * up) * perPixel;
}

class Viewer {
public:
    Viewer(Options& o, const ViewOptions& v, ink::Context& ctx, Scene& scene, GLFWwindow* window, VkSurfaceKHR surface);
    ~Viewer() { release(); }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    ViewResult run();

    // GLFW callbacks: they only record what to do, the loop does it (no Vulkan work, nothing that throws).
    void onKey(int key, int action);
    void onCursor(double x, double y);
    void onScroll(double dy);
    void onResize() { resized_ = true; }

private:
    bool ensureSwapchain();
    bool drawFrame(const std::string& screenshot);
    void record(Frame& f, uint32_t image, bool capture);
    void submitAndPresent(Frame& f, uint32_t image, bool suboptimal);
    void saveCapture(Frame& f, const std::string& path);
    void refine();
    void updateTitle(double averageMs);
    std::string nextScreenshotPath();
    void saveVector();  // the marks of the frame drawn last, to --vector or the next free inkwell-view-N.svg
    bool quitting() const { return quit_ || glfwWindowShouldClose(window_); }
    void release();

    Options& o_;
    ViewOptions v_;
    ink::Context& ctx_;
    Scene& scene_;
    GLFWwindow* window_;
    VkSurfaceKHR surface_;
    VkSurfaceFormatKHR format_{};
    ink::Swapchain swapchain_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::array<Frame, kFramesInFlight> frames_{};
    uint32_t current_ = 0;
    std::unique_ptr<ink::PointRenderer> renderer_;
    uint64_t points_ = 0;

    ink::Camera camera_, home_;
    glm::vec3 tracedEye_{NAN}, previousEye_{NAN};  // where the contours were traced from; the last frame's eye
    DrawStyle appliedStyle_;
    uint32_t appliedLevels_;
    float toneGamma_;  // what T restores
    size_t light_ = 0;
    double lastX_ = 0, lastY_ = 0;
    bool resized_ = false, quit_ = false, restyle_ = true, rerefine_ = false, screenshotKey_ = false;
    bool vectorKey_ = false;
};

Viewer& viewerOf(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

Viewer::Viewer(Options& o, const ViewOptions& v, ink::Context& ctx, Scene& scene, GLFWwindow* window,
               VkSurfaceKHR surface)
    : o_(o),
      v_(v),
      ctx_(ctx),
      scene_(scene),
      window_(window),
      surface_(surface),
      camera_(cameraFrom(o)),
      home_(camera_),
      appliedStyle_(o.style),
      appliedLevels_(o.refine.levels),
      toneGamma_(o.render.toneGamma > 0 ? o.render.toneGamma : 1.5f) {
    try {
        format_ = ink::chooseSurfaceFormat(ctx, surface);
        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = ctx.queueFamily;
        VK_CHECK(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &pool_));
        for (Frame& f : frames_) {
            VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            alloc.commandPool = pool_;
            alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            alloc.commandBufferCount = 1;
            VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, &f.cmd));
            VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
            fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
            VK_CHECK(vkCreateFence(ctx.device, &fenceInfo, nullptr, &f.done));
            VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
            VK_CHECK(vkCreateSemaphore(ctx.device, &semaphoreInfo, nullptr, &f.acquired));
        }
        renderer_ = std::make_unique<ink::PointRenderer>(ctx, scene.pointers(), format_.format, kFramesInFlight,
                                                         scene.strokes.get());
        points_ = scene.points();
    } catch (...) {
        release();
        throw;
    }
    glfwSetWindowUserPointer(window, this);
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) { viewerOf(w).onKey(key, action); });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) { viewerOf(w).onCursor(x, y); });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) { viewerOf(w).onScroll(dy); });
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) { viewerOf(w).onResize(); });
    glfwGetCursorPos(window, &lastX_, &lastY_);
}

// Reverse order of creation; safe on a partly constructed viewer.
void Viewer::release() {
    glfwSetKeyCallback(window_, nullptr);
    glfwSetCursorPosCallback(window_, nullptr);
    glfwSetScrollCallback(window_, nullptr);
    glfwSetFramebufferSizeCallback(window_, nullptr);
    glfwSetWindowUserPointer(window_, nullptr);
    vkDeviceWaitIdle(ctx_.device);
    renderer_.reset();
    for (Frame& f : frames_) {
        if (f.capture.buffer) ink::destroyBuffer(ctx_, f.capture);
        vkDestroySemaphore(ctx_.device, f.acquired, nullptr);
        vkDestroyFence(ctx_.device, f.done, nullptr);
        f = Frame{};
    }
    vkDestroyCommandPool(ctx_.device, pool_, nullptr);  // frees the command buffers
    pool_ = VK_NULL_HANDLE;
    ink::destroySwapchain(ctx_, swapchain_);
}

void Viewer::onKey(int key, int action) {
    bool press = action == GLFW_PRESS, repeat = action == GLFW_REPEAT;
    if (!press && !(repeat && (key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET))) return;
    ink::RenderStyle& s = o_.render;
    switch (key) {
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q:
            quit_ = true;
            break;
        case GLFW_KEY_1:
            o_.style = DrawStyle::Stipple;
            break;
        case GLFW_KEY_2:
            o_.style = DrawStyle::Direction;
            break;
        case GLFW_KEY_3:
            o_.style = DrawStyle::Both;
            break;
        case GLFW_KEY_EQUAL:  // '+' is shift+'=' on most layouts; '=' alone counts too
        case GLFW_KEY_KP_ADD:
            o_.refine.levels = std::min(o_.refine.levels + 1, kMaxLevels);
            break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT:
            o_.refine.levels = o_.refine.levels > 0 ? o_.refine.levels - 1 : 0;
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
            static constexpr ink::UpAxis kOrder[] = {ink::UpAxis::PosY, ink::UpAxis::PosZ, ink::UpAxis::PosX,
                                                     ink::UpAxis::NegY, ink::UpAxis::NegZ, ink::UpAxis::NegX};
            size_t k = 0;
            while (kOrder[k] != s.up) ++k;
            s.up = kOrder[(k + 1) % 6];
            camera_.up = home_.up = s.up;
            restyle_ = true;  // the light is fixed to the model as seen from the default camera of this axis
            break;
        }
        case GLFW_KEY_S:
            screenshotKey_ = true;
            break;
        case GLFW_KEY_V:
            vectorKey_ = true;
            break;
        case GLFW_KEY_R:
            camera_ = home_;
            break;
        default:
            break;
    }
    if (o_.style != appliedStyle_ || o_.refine.levels != appliedLevels_) rerefine_ = true;
}

void Viewer::onCursor(double x, double y) {
    double dx = x - lastX_, dy = y - lastY_;
    lastX_ = x;
    lastY_ = y;
    bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                 glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    if (right || (left && shift)) {
        pan(camera_, dx, dy, swapchain_.extent.height);
    } else if (left) {
        // Grab-and-turn: dragging right turns the model right, i.e. the camera goes left around it.
        camera_.azimuthDeg = std::fmod(camera_.azimuthDeg - float(dx) * 0.3f, 360.0f);
        camera_.elevationDeg = std::clamp(camera_.elevationDeg + float(dy) * 0.3f, -89.0f, 89.0f);
    }
}

void Viewer::onScroll(double dy) {
    camera_.distance = std::clamp(camera_.distance * float(std::pow(0.9, dy)), 0.1f, 50.0f);
}

// (Re)creates the swapchain when there is none or the window changed; false while the window has no area.
bool Viewer::ensureSwapchain() {
    if (swapchain_.swapchain && !resized_) return true;
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    if (!ink::createSwapchain(ctx_, swapchain_, surface_, format_, {uint32_t(width), uint32_t(height)})) return false;
    resized_ = false;
    if (!v_.screenshot.empty() && !swapchain_.copyable)
        throw ink::Error("this window system's images cannot be copied, so --screenshot cannot work");
    return true;
}

// Re-refines on the device after a style or level key, then rebuilds the renderer over the new points.
void Viewer::refine() {
    rerefine_ = false;
    VK_CHECK(vkDeviceWaitIdle(ctx_.device));
    renderer_.reset();  // it holds descriptors of the old refinement's buffers
    try {
        scene_.refine(o_);
    } catch (const ink::Error& e) {
        // Too many points for this device, say: keep viewing what was there.
        ink::note(std::string(e.what()) + "; keeping " + ink::drawStyleName(appliedStyle_) + " at " +
                  std::to_string(appliedLevels_) + " levels");
        o_.style = appliedStyle_;
        o_.refine.levels = appliedLevels_;
        scene_.refine(o_);
    }
    appliedStyle_ = o_.style;
    appliedLevels_ = o_.refine.levels;
    renderer_ = std::make_unique<ink::PointRenderer>(ctx_, scene_.pointers(), format_.format, kFramesInFlight,
                                                     scene_.strokes.get());
    tracedEye_ = glm::vec3(NAN);
    points_ = scene_.points();
    restyle_ = true;  // the new renderer's style block is empty
}

void Viewer::record(Frame& f, uint32_t index, bool capture) {
    // The contour depends on the eye: traced again once the eye stops (a frame without motion), since tracing
    // takes longer than a frame (docs/lines.md); while it moves, the last view's contour is drawn.
    if (scene_.lines.contours && camera_.eye() != tracedEye_ && camera_.eye() == previousEye_) {
        scene_.traceContours(camera_);
        tracedEye_ = camera_.eye();
    }
    previousEye_ = camera_.eye();
    VkCommandBuffer cmd = f.cmd;
    VK_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    if (restyle_) {
        renderer_->setStyle(cmd, o_.render, 1.0f);
        restyle_ = false;
    }
    // The acquire semaphore is waited on at colour output: the image's transition comes after that stage.
    ink::FrameTarget target{swapchain_.images[index], swapchain_.views[index], swapchain_.extent,
                            VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT};
    renderer_->recordFrame(cmd, camera_, target, current_, capture ? &f.capture : nullptr);
    VK_CHECK(vkEndCommandBuffer(cmd));
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
    VK_CHECK(vkQueueSubmit2(ctx_.queue, 1, &submit, f.done));

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &swapchain_.rendered[index];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_.swapchain;
    present.pImageIndices = &index;
    VkResult presented = vkQueuePresentKHR(ctx_.queue, &present);
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || suboptimal)
        resized_ = true;  // recreated before the next frame
    else
        VK_CHECK(presented);
}

// Draws and presents one frame, saving it to `screenshot` when that is not empty. False when the
// swapchain was out of date and nothing was drawn (it is recreated before the next try).
bool Viewer::drawFrame(const std::string& screenshot) {
    Frame& f = frames_[current_];
    VK_CHECK(vkWaitForFences(ctx_.device, 1, &f.done, VK_TRUE, UINT64_MAX));
    uint32_t index = 0;
    VkResult acquired =
        vkAcquireNextImageKHR(ctx_.device, swapchain_.swapchain, UINT64_MAX, f.acquired, VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        resized_ = true;
        return false;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) VK_CHECK(acquired);
    // Only now: a frame that returned above must leave the fence signalled for the next wait.
    VK_CHECK(vkResetFences(ctx_.device, 1, &f.done));

    bool capture = !screenshot.empty();
    if (capture) {
        VkDeviceSize bytes = VkDeviceSize(swapchain_.extent.width) * swapchain_.extent.height * 4;
        f.capture = ink::createBuffer(ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, ink::MemoryUse::Readback);
    }
    record(f, index, capture);
    submitAndPresent(f, index, acquired == VK_SUBOPTIMAL_KHR);
    if (capture) saveCapture(f, screenshot);
    current_ = (current_ + 1) % kFramesInFlight;
    return true;
}

void Viewer::saveCapture(Frame& f, const std::string& path) {
    VK_CHECK(vkWaitForFences(ctx_.device, 1, &f.done, VK_TRUE, UINT64_MAX));
    // Captured at the extent the frame was recorded with (a resize only takes effect before the next one).
    VkExtent2D extent = swapchain_.extent;
    ink::RgbaImage image{extent.width, extent.height, {}};
    const uint8_t* mapped = static_cast<const uint8_t*>(f.capture.mapped);
    image.pixels.assign(mapped, mapped + f.capture.size);
    ink::destroyBuffer(ctx_, f.capture);
    ink::swizzleToRgba(format_.format, image.pixels);
    ink::writePng(path, image);
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
    writeVectorView(*renderer_, frame, path, o_.page);
    std::printf("view: saved %s\n", path.c_str());
}

void Viewer::updateTitle(double averageMs) {
    char title[256];
    std::snprintf(title, sizeof(title), "inkwell view - %s - %s, %u levels - %llu points - %.1f ms",
                  std::filesystem::path(o_.model).filename().c_str(), ink::drawStyleName(o_.style), o_.refine.levels,
                  (unsigned long long)points_, averageMs);
    glfwSetWindowTitle(window_, title);
}

ViewResult Viewer::run() {
    ViewResult result;
    auto previous = Clock::now(), titleStart = previous;
    double titleMs = 0;
    uint32_t titleFrames = 0;
    bool savedLast = false, savedVectorLast = false;
    while (!quitting()) {
        glfwPollEvents();
        if (rerefine_) {
            refine();
            previous = Clock::now();  // the refinement is not a frame
        }
        if (glfwGetWindowAttrib(window_, GLFW_ICONIFIED) || !ensureSwapchain()) {
            glfwWaitEvents();  // minimized: nothing to draw until the window is back
            previous = Clock::now();
            continue;
        }
        bool last = v_.frames > 0 && result.frames + 1 == v_.frames;
        std::string screenshot;
        if (screenshotKey_ || (last && !v_.screenshot.empty())) screenshot = nextScreenshotPath();
        bool fromKey = screenshotKey_;
        bool drawn = false;
        try {
            drawn = drawFrame(screenshot);
        } catch (const ink::Error& e) {
            if (!fromKey) throw;
            ink::note(std::string("screenshot not saved: ") + e.what());  // an S key failure keeps the view
            screenshotKey_ = false;
            continue;
        }
        if (!drawn) continue;
        if (!screenshot.empty()) {
            std::printf("view: saved %s\n", screenshot.c_str());
            screenshotKey_ = false;
            savedLast = last;
        }
        if (vectorKey_ || (last && !v_.vector.empty())) {
            try {
                saveVector();
                savedVectorLast = last;
            } catch (const ink::Error& e) {
                if (!vectorKey_) throw;
                ink::note(std::string("drawing not saved: ") + e.what());  // a V key failure keeps the view
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
            updateTitle(titleMs / titleFrames);
            titleStart = now;
            titleMs = 0;
            titleFrames = 0;
        }
        if (v_.frames > 0 && result.frames >= v_.frames) break;
    }
    // Closed or quit before a --screenshot was taken: draw one more frame for it.
    for (int attempt = 0; !v_.screenshot.empty() && !savedLast && attempt < 3; ++attempt)
        if (ensureSwapchain() && drawFrame(v_.screenshot)) {
            std::printf("view: saved %s\n", v_.screenshot.c_str());
            savedLast = true;
        }
    if (!v_.screenshot.empty() && !savedLast) ink::note("no frame to save to " + v_.screenshot + " (minimized?)");
    if (!v_.vector.empty() && !savedVectorLast) {
        if (result.frames > 0)
            saveVector();  // closed before the last frame: the frame drawn last
        else
            ink::note("no frame to save to " + v_.vector + " (minimized?)");
    }
    VK_CHECK(vkDeviceWaitIdle(ctx_.device));
    result.extent = swapchain_.extent;
    result.points = points_;
    result.controlPoints = scene_.model.fit.controlPoints;
    return result;
}

int runView(Options& o, const ViewOptions& v) {
    finishOptions(o);
    ink::checkOutputs({v.screenshot, v.vector, o.statsPath}, {o.model, o.preset});  // before the window opens
    if (!v.vector.empty() && !ink::isVectorPath(v.vector))
        throw ink::Error("--vector '" + v.vector + "' is not an .svg or .pdf file");
    VkExtent2D size = kDefaultWindow;
    if (o.command && o.command->count("--size")) size = {o.size[0], o.size[1]};

    GlfwLibrary glfw;
    Window window(size, "inkwell view - " + std::filesystem::path(o.model).filename().string());
    Session session(o, GlfwLibrary::instanceExtensions(), true);
    ViewResult result;
    // With --screenshot or --vector (every save then goes to that one file), they and the stats are renamed into place
    // together once both are written; S-key screenshots to fresh names are saved at once.
    std::optional<ink::OutputBatch> outputs;
    if (!v.screenshot.empty() || !v.vector.empty()) outputs.emplace();
    {
        Surface surface(session.ctx.instance, window.handle);
        ink::checkPresentSupport(session.ctx, surface.surface);
        Scene scene(session.ctx, o);
        glfwShowWindow(window.handle);
        Viewer viewer(o, v, session.ctx, scene, window.handle, surface.surface);
        result = viewer.run();
    }
    session.checkValidation();

    double medianMs = medianFrameMs(result.frameMs);
    json stats = {{"frames", result.frames},
                  {"median_frame_ms", medianMs},
                  {"frame_ms", result.frameMs},
                  {"width", result.extent.width},
                  {"height", result.extent.height},
                  {"points", result.points},
                  {"control_points", result.controlPoints}};
    stats.update(deviceJson(session.ctx));
    writeJson(o.statsPath, stats);
    if (outputs) outputs->commit();
    std::printf("view: %u frames, median %.2f ms (%ux%u, %llu points)\n", result.frames, medianMs, result.extent.width,
                result.extent.height, (unsigned long long)result.points);
    return 0;
}

}  // namespace

void addViewCommand(CLI::App& cli, Options& o, Commands& commands) {
    auto v = std::make_shared<ViewOptions>();
    CLI::App* view = cli.add_subcommand("view", "Open a window and view a model interactively (docs/viewer.md)");
    addModelOptions(view, o);
    addRefineOptions(view, o);
    addRenderOptions(view, o);
    addVectorOptions(view, o);
    addDeviceOptions(view, o);
    view->get_option("--size")->description("Window width and height in pixels")->default_str("[1024,768]");
    // The window is drawn at its own resolution every frame; supersampling is for `render`.
    view->remove_option(view->get_option("--supersample"));
    view->add_option("--frames", v->frames, "Quit after this many frames (default: when the window closes)");
    view->add_option("--screenshot", v->screenshot, "Save the last frame (or the S key's) to this PNG");
    view->add_option("--vector", v->vector,
                     "Save the last frame's marks (or the V key's) to this SVG or PDF (page options as render's)");
    commands.emplace_back(view, [&o, v] { return runView(o, *v); });
}

}  // namespace app
