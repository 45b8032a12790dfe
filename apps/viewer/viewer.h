// The viewer's window loop (`inkwell view`, docs/viewer.md): a FIFO swapchain and two frames in flight; every frame
// an inkwell::FrameRecorder draws straight into the swapchain image (no readback unless a screenshot is asked
// for), and the settings panel (viewer_panel.h) beside it. The keys, the mouse and the panel only set state
// (viewer_input.cpp); the frame loop (viewer.cpp) applies it between frames. New refinements run on a worker
// thread (Drawing::prepare), and are put in place between frames (Drawing::apply). On the public API alone.
#pragma once

#include "../cli/app.h"
#include "viewer_panel.h"
#include "vulkan.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

struct GLFWwindow;

namespace app {

inline constexpr uint32_t kFramesInFlight = 2;
inline constexpr VkExtent2D kDefaultWindow{1024, 768};  // fits a 1280×1024 screen with its decorations
inline constexpr uint32_t kMaxLevels = 8;               // the +/- keys stay in 0..8
inline constexpr double kTitleInterval = 0.5;           // seconds between window title updates

// Where the L key sends the light, as seen from the default camera (x right, y up, z towards the viewer); it
// stays fixed to the model unless --light-follows-camera.
inline constexpr std::array<std::array<float, 3>, 5> kLights{{
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

struct Frame {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;          // created signalled: the first wait returns at once
    VkSemaphore acquired = VK_NULL_HANDLE;  // the swapchain image is ready to be drawn into
};

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A new refinement, or new pen lines over the current one, made on a worker thread while the window keeps
// handling events (Drawing::prepare). The frames stop meanwhile: the device runs one queue in order, so a frame
// submitted after the refinement would wait for it anyway, and the worker has the queue to itself.
struct RefineJob {
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
    bool stale() const { return !(o_.drawing == drawing_.options()); }
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
    bool quitting() const;
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
    float toneGamma_;                                     // what T restores
    size_t light_ = 0;
    double lastX_ = 0, lastY_ = 0;
    bool resized_ = false, quit_ = false, restyle_ = true, rerefine_ = false, screenshotKey_ = false;
    bool vectorKey_ = false;
    bool dragging_ = false;  // a drag that began on the drawing (not on the panel) moves the camera
};

}  // namespace app
