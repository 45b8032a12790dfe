// The viewer's frame loop (viewer.h): the device's objects, the swapchain, refinements put in place, frames
// recorded, submitted and presented, screenshots.
#include "viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace app {

namespace {
Viewer& viewerOf(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }
}  // namespace

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
    const inkwell::Drawing::Work work = drawing_.work(o_.drawing);
    if (work == inkwell::Drawing::Work::None) {
        drawing_.apply(drawing_.prepare(o_.drawing, reporter()));  // nothing to make or trace
        restyle_ = true;
        say(std::string("contours ") + (o_.drawing.contours ? "on" : "off"), false);
        return;
    }
    job_ = std::make_unique<RefineJob>();
    RefineJob* job = job_.get();
    job->options = o_.drawing;
    job->tracing = work != inkwell::Drawing::Work::Sets;  // else once the sets are made
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
        o_.drawing = drawing_.options();
        say(job->error + "; keeping " + styleName(o_) + " at " + std::to_string(o_.drawing.levels) + " levels", true);
        return;
    }
    const bool refined = job->pending.refined(), traced = job->pending.traced();
    const double seconds = job->pending.seconds(), traceSeconds = job->pending.traceSeconds();
    const size_t strokes = job->pending.hatchStrokes();
    drawing_.apply(std::move(job->pending));
    const inkwell::DrawingOptions& applied = job->options;  // drawing_.options() now
    restyle_ = true;
    std::string message;
    if (refined) {
        points_ = drawing_.pointCount();
        char line[160];
        std::snprintf(line, sizeof line, "refined %s at %u levels in %.2f s: %llu points",
                      inkwell::styleName(applied.style), applied.levels, seconds, (unsigned long long)points_);
        message = line;
    }
    if (traced && applied.hatching) {
        char line[120];
        std::snprintf(line, sizeof line, "%shatching traced in %.2f s: %zu strokes", message.empty() ? "" : "; ",
                      traceSeconds, strokes);
        message += line;
    } else if (!refined) {
        message = std::string("pen lines: ") + (applied.contours ? "contours" : "none");
    }
    say(message, false);
    // Changed again while it ran: once more.
    if (stale()) rerefine_ = true;
}

VkExtent2D Viewer::drawingExtent() const {
    VkExtent2D e = swapchain_.extent;
    if (panel_) e.width = panel_->drawingWidth(e.width);
    return e;
}

bool Viewer::panelDrawn() const { return panel_ && drawingExtent().width < swapchain_.extent.width; }

void Viewer::record(Frame& f, uint32_t index, bool capture) {
    // The contour depends on the eye: traced again every frame while a trace takes under kTraceBudget (the device's
    // tracer on a GPU, a few milliseconds), else once the eye stops (a frame without motion; the CPU tracer on
    // lavapipe takes 35–45 ms for the bunny), the last view's contour drawn while it moves (docs/lines.md).
    constexpr double kTraceBudget = 0.008;
    const std::array<float, 3> eye = camera_.eye();
    const bool moving = eye != previousEye_;
    const bool trace = !moving || (traced_ && drawing_.contourSeconds() < kTraceBudget);
    traced_ |= trace && drawing_.options().contours;
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
    else if (presented != VK_SUCCESS)
        viewer::vkFail("vkQueuePresentKHR", presented, __FILE__, __LINE__);
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
    if (acquired != VK_SUCCESS && acquired != VK_SUBOPTIMAL_KHR)
        viewer::vkFail("vkAcquireNextImageKHR", acquired, __FILE__, __LINE__);
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

bool Viewer::quitting() const { return quit_ || glfwWindowShouldClose(window_); }

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

}  // namespace app
