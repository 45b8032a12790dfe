// The viewer's settings panel (docs/viewer.md): a Dear ImGui window beside the drawing, with its own render pass
// drawn over the swapchain image after the drawing (and after any screenshot's copy, so that saved images never
// show it). Only the inkwell executable uses ImGui; the engine library knows nothing of it.
#pragma once

#include "../cli/app.h"
#include "vulkan.h"

#include <cstdint>
#include <string>

struct GLFWwindow;

namespace app {

// What the panel shows besides the options it edits.
struct PanelInfo {
    std::string model;
    size_t controlPoints = 0;
    uint64_t points = 0;
    double frameMs = 0;             // averaged over the last half second
    bool refining = false;          // a new refinement is being made (the settings that need one wait)
    double refineProgress = 0;      // 0..1
    const char* task = "refining";  // or "tracing the lines" (no progress to show)
    std::string message;            // the last thing done or refused ("saved x.png", an error)
    std::string screenshotPath;     // the S key's next file
    std::string pngPath;            // the PNG file the panel offers first
    VkExtent2D drawing{0, 0};       // the drawing's size in the window
    const char* autoUp = nullptr;   // the up axis `--up auto` found ("y", ...), when the viewer started with it

    bool operator==(const PanelInfo& o) const {
        return model == o.model && controlPoints == o.controlPoints && points == o.points && frameMs == o.frameMs &&
               refining == o.refining && refineProgress == o.refineProgress && std::string(task) == o.task &&
               message == o.message && screenshotPath == o.screenshotPath && pngPath == o.pngPath &&
               drawing.width == o.drawing.width && drawing.height == o.drawing.height && autoUp == o.autoUp;
    }
};

// What the panel was asked to do in one frame; the viewer does it between frames.
struct PanelActions {
    bool restyle = false;   // a drawing setting changed: upload the style
    bool rerefine = false;  // style, levels, passes, direction or distribution changed: refine again
    bool resetCamera = false;
    bool copyCamera = false, pasteCamera = false;  // the camera as text on the clipboard, or from it
    bool upChanged = false;                        // the up axis changed (the camera's and the home view's)
    bool upAuto = false;   // back to the up axis and the first picture `--up auto` chose (PanelInfo::autoUp)
    bool savePng = false;  // pngPath (.png, .svg or .pdf) at pngSize, as `inkwell render` draws it
    bool saveScreenshot = false;
    bool savePreset = false, loadPreset = false;  // presetPath
    std::string pngPath, presetPath;
    uint32_t pngSize[2] = {0, 0};
};

class ViewerPanel {
public:
    static constexpr uint32_t kWidth = 320;  // pixels, at the window's right

    // `framesInFlight`: the panel's vertex buffers are used in turn, one set a frame.
    ViewerPanel(const viewer::Gpu& gpu, GLFWwindow* window, VkFormat format, uint32_t framesInFlight);
    ~ViewerPanel();
    ViewerPanel(const ViewerPanel&) = delete;
    ViewerPanel& operator=(const ViewerPanel&) = delete;

    bool shown() const { return shown_; }
    void toggle() {
        shown_ = !shown_;
        inputArrived();
    }
    void showHelp() {
        shown_ = true;
        help_ = true;
        inputArrived();
    }
    // The viewer calls this for every window event, which the panel may have to answer: build() makes the panel
    // anew for the next few frames. Without events, and with nothing new to show, the last frame's panel stays.
    void inputArrived() { framesToBuild_ = 3; }
    // The window's width left to the drawing.
    uint32_t drawingWidth(uint32_t windowWidth) const {
        return shown_ && windowWidth > kWidth + 16 ? windowWidth - kWidth : windowWidth;
    }
    // Whether the last frame's panel takes the mouse (it is over the panel, or dragging one of its widgets) or
    // the keyboard (a text field is being edited): the viewer leaves those events to it.
    bool wantsMouse() const;
    bool wantsKeyboard() const;

    // Builds the panel's widgets for one frame over `o` and `camera` (edited in place), unless nothing came in or
    // changed since the last frame's (then it asks for nothing).
    PanelActions build(Options& o, inkwell::Camera& camera, const PanelInfo& info);
    // The layout the drawing leaves the swapchain image in for record(): TRANSFER_DST_OPTIMAL when the panel is
    // copied in from its own image (the panel alone, on a swapchain that takes copies), else
    // COLOR_ATTACHMENT_OPTIMAL (a popup over the drawing: drawn straight into the swapchain image).
    VkImageLayout layoutBefore(const viewer::Swapchain& swapchain, uint32_t drawingWidth) const;
    // Records the panel into swapchain image `index` after the drawing, leaving it in PRESENT_SRC_KHR. The panel's
    // own image is drawn again only when the panel's triangles changed (ImGui draws them anew every frame, but
    // they change only when something in the panel does); every frame copies it in. The swapchain's views are
    // those of its last (re)creation.
    void record(VkCommandBuffer cmd, const viewer::Swapchain& swapchain, uint32_t index, uint32_t drawingWidth);
    // After the swapchain was recreated (the device is idle then): the framebuffers follow on the next record.
    void swapchainChanged() { releaseFramebuffers(); }

private:
    void releaseFramebuffers();
    void release();
    bool direct(const viewer::Swapchain& swapchain, uint32_t drawingWidth) const;
    void ensureCache(VkFormat format, VkExtent2D extent);

    const viewer::Gpu& gpu_;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;
    std::vector<VkFramebuffer> framebuffers_;
    // The panel drawn once: its image (the window's right part), the render pass that clears and draws it, and
    // the signature of the triangles it holds.
    viewer::Image cache_;
    VkRenderPass cachePass_ = VK_NULL_HANDLE;
    VkFramebuffer cacheFramebuffer_ = VK_NULL_HANDLE;
    std::vector<uint8_t> drawn_, signature_;
    bool cacheValid_ = false;
    bool fresh_ = false;  // build() made new triangles since the last record()
    bool shown_ = true, help_ = false, built_ = false;
    std::string pngPath_, presetPath_ = "inkwell-preset.json";
    int pngSize_[2] = {0, 0};
    float toneGamma_ = 1.5f;                 // what the tone checkbox restores
    int levelsEdit_ = -1, passesEdit_ = -1;  // while their sliders are held
    float spacingEdit_ = -1;
    int framesToBuild_ = 3;
    PanelInfo builtInfo_;
    double builtAt_ = 0;
};

}  // namespace app
