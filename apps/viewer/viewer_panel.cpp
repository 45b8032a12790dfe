// The viewer's panel (viewer_panel.h): Dear ImGui, from Debian's libimgui-dev with its GLFW and Vulkan
// backends. ImGui 1.86's Vulkan backend draws inside a render pass of ours: one subpass over the swapchain image,
// loaded (the drawing is in it), ending in PRESENT_SRC_KHR.
#include "viewer_panel.h"

#include "inkwell/ranges.h"

#include "../cli/preset.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace app {

namespace {

// ImGui's backend reports Vulkan failures through this hook.
void checkVk(VkResult result) {
    if (result < 0) throw inkwell::Error(std::string("the viewer's panel: ") + viewer::resultName(result));
}

// The mouse and keys, for the "?" help (docs/viewer.md has the same table).
constexpr const char* kHelp[][2] = {
    {"left drag", "orbit (turntable: the up axis stays up)"},
    {"right drag, shift + left drag", "pan"},
    {"wheel", "zoom"},
    {"1 / 2 / 3", "style: stipple / direction / both"},
    {"+ / -", "refinement levels"},
    {"[ / ]", "tau, the silhouette threshold"},
    {"T", "tone on/off"},
    {"H", "hidden lines on/off"},
    {"O", "occlusion on/off"},
    {"U", "the next up axis (and back to auto, the first picture)"},
    {"L", "the next light direction"},
    {"S", "screenshot of the drawing"},
    {"V", "the drawing's marks as SVG (--vector)"},
    {"ctrl + C / ctrl + V", "copy / paste the camera"},
    {"R", "reset the camera"},
    {"Tab", "hide/show this panel"},
    {"F1", "this help"},
    {"Esc, Q", "quit"},
    {"ctrl + click a slider", "type a value"},
};

constexpr inkwell::Up kUpOrder[] = {inkwell::Up::Y,    inkwell::Up::Z,    inkwell::Up::X,
                                    inkwell::Up::NegY, inkwell::Up::NegZ, inkwell::Up::NegX};
constexpr char kUpNames[] = "y\0z\0x\0-y\0-z\0-x\0";

// The sliders span the usual part of each setting's range; every span lies within the range of the one table
// the command line, the presets and the API check against (include/inkwell/ranges.h): a span outside does not
// compile (the consteval constructor throws).
struct Span {
    float lo, hi;
    consteval Span(const inkwell::Range& range, float low, float high) : lo(low), hi(high) {
        if (!range.contains(low) || !range.contains(high)) throw "a slider's span lies outside its range";
    }
};
namespace ranges = inkwell::ranges;
constexpr Span kToneSpan{ranges::toneGamma, 0.1f, 8.0f};
constexpr Span kInkDensitySpan{ranges::inkDensity, 0.0f, 4.0f};
constexpr Span kDotSpan{ranges::dotSize, 0.5f, 8.0f};
constexpr Span kTauSpan{ranges::tau, 0.0f, 0.9f};
constexpr Span kContourPenSpan{ranges::penWidth, 0.25f, 12.0f};
constexpr Span kHaloSpan{ranges::halo, 0.0f, 16.0f};
constexpr Span kFinePenSpan{ranges::penWidth, 0.25f, 8.0f};
constexpr Span kHiddenDotSpan{ranges::dotSize, 0.25f, 8.0f};
constexpr Span kHiddenInkSpan{ranges::hiddenOpacity, 0.05f, 1.0f};
constexpr Span kHatchSpacingSpan{ranges::hatchSpacing, 0.002f, 0.05f};

// A slider for a setting that needs a new refinement: the value is taken when the slider is let go (or a typed
// value entered), not at every step of a drag. `editing` holds the value while the slider is held.
bool sliderOnRelease(const char* label, uint32_t& value, int lo, int hi, int& editing) {
    int v = editing >= 0 ? editing : int(value);
    ImGui::SliderInt(label, &v, lo, hi, "%d", ImGuiSliderFlags_AlwaysClamp);
    bool done = ImGui::IsItemDeactivatedAfterEdit();
    editing = ImGui::IsItemActive() ? v : -1;
    if (done && uint32_t(v) != value) {
        value = uint32_t(v);
        return true;
    }
    return false;
}

// The same for a float, on a logarithmic scale.
bool sliderOnRelease(const char* label, double& value, float lo, float hi, const char* format, float& editing) {
    float v = editing >= 0 ? editing : float(value);
    ImGui::SliderFloat(label, &v, lo, hi, format, ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
    bool done = ImGui::IsItemDeactivatedAfterEdit();
    editing = ImGui::IsItemActive() ? v : -1;
    if (done && double(v) != value) {
        value = double(v);
        return true;
    }
    return false;
}

}  // namespace

ViewerPanel::ViewerPanel(const viewer::Gpu& gpu, GLFWwindow* window, VkFormat format, uint32_t framesInFlight)
    : gpu_(gpu) {
    const VkDevice device = gpu.vk.device;
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini left in the current directory
    io.LogFilename = nullptr;
    ImGui::StyleColorsLight();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 0;
    style.FramePadding.y = 2;  // compact: the whole panel fits a 768-pixel window
    style.ItemSpacing.y = 3;
    style.WindowBorderSize = 0;
    style.Colors[ImGuiCol_WindowBg].w = 1.0f;  // opaque: nothing of the frame's undefined pixels shows through
    try {
        if (!ImGui_ImplGlfw_InitForVulkan(window, false))  // the viewer forwards the events it gets
            throw inkwell::Error("the viewer's panel cannot start on this window");

        VkAttachmentDescription attachment{};
        attachment.format = format;
        attachment.samples = VK_SAMPLE_COUNT_1_BIT;
        attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the drawing, left of the panel
        attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        attachment.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        attachment.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
        VkSubpassDescription subpass{};
        subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        subpass.colorAttachmentCount = 1;
        subpass.pColorAttachments = &reference;
        // Two passes below, one into the swapchain image and one into the panel's own image, with the same
        // dependencies (ImGui's pipeline is made for the first, and drawing in the second needs them compatible):
        // after the drawing's writes (the renderer's last barrier makes them available to all commands) or the
        // copies of earlier frames out of the panel's image; before the copy out of it (presentation is ordered by
        // the submission's semaphore).
        VkSubpassDependency dependencies[2] = {};
        dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
        dependencies[0].dstSubpass = 0;
        dependencies[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
        dependencies[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        dependencies[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        dependencies[1].srcSubpass = 0;
        dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
        dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
        dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        VkRenderPassCreateInfo passInfo{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        passInfo.attachmentCount = 1;
        passInfo.pAttachments = &attachment;
        passInfo.subpassCount = 1;
        passInfo.pSubpasses = &subpass;
        passInfo.dependencyCount = 2;
        passInfo.pDependencies = dependencies;
        VIEWER_CHECK(vkCreateRenderPass(device, &passInfo, nullptr, &renderPass_));

        // The panel's own image: cleared to the panel's background, drawn, left for copying.
        attachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        attachment.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        attachment.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        VIEWER_CHECK(vkCreateRenderPass(device, &passInfo, nullptr, &cachePass_));

        // The font texture's one descriptor.
        VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = 1;
        poolInfo.pPoolSizes = &size;
        VIEWER_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &descriptorPool_));

        ImGui_ImplVulkan_InitInfo init{};
        init.Instance = gpu.vk.instance;
        init.PhysicalDevice = gpu.vk.physicalDevice;
        init.Device = device;
        init.QueueFamily = gpu.vk.queueFamily;
        init.Queue = gpu.vk.queue;
        init.DescriptorPool = descriptorPool_;
        init.MinImageCount = std::max(2u, framesInFlight);
        init.ImageCount = std::max(2u, framesInFlight);
        init.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
        init.CheckVkResultFn = checkVk;
        if (!ImGui_ImplVulkan_Init(&init, renderPass_)) throw inkwell::Error("the viewer's panel cannot start");
        viewer::submitAndWait(gpu, [](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
        ImGui_ImplVulkan_DestroyFontUploadObjects();
    } catch (...) {
        release();
        throw;
    }
}

// The viewer waits for the device to be idle before it lets the panel go.
ViewerPanel::~ViewerPanel() { release(); }

void ViewerPanel::release() {
    if (ImGui::GetCurrentContext()) {
        if (ImGui::GetIO().BackendRendererUserData) ImGui_ImplVulkan_Shutdown();
        if (ImGui::GetIO().BackendPlatformUserData) ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    releaseFramebuffers();
    vkDestroyDescriptorPool(gpu_.vk.device, descriptorPool_, nullptr);
    vkDestroyRenderPass(gpu_.vk.device, renderPass_, nullptr);
    vkDestroyRenderPass(gpu_.vk.device, cachePass_, nullptr);
    descriptorPool_ = VK_NULL_HANDLE;
    renderPass_ = cachePass_ = VK_NULL_HANDLE;
}

void ViewerPanel::releaseFramebuffers() {
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(gpu_.vk.device, f, nullptr);
    framebuffers_.clear();
    vkDestroyFramebuffer(gpu_.vk.device, cacheFramebuffer_, nullptr);
    cacheFramebuffer_ = VK_NULL_HANDLE;
    if (cache_.image) viewer::destroyImage(gpu_, cache_);
    cacheValid_ = false;
}

// Straight into the swapchain image when something of the panel (a popup, the help) lies over the drawing, or
// the swapchain's images cannot be copied into.
bool ViewerPanel::direct(const viewer::Swapchain& swapchain, uint32_t drawingWidth) const {
    if (!swapchain.copyTarget) return true;
    const ImDrawData* data = ImGui::GetDrawData();
    if (!data || !data->Valid) return false;
    // By the triangles, not their clip rectangles (a window's background is clipped to the whole display).
    for (int l = 0; l < data->CmdListsCount; ++l)
        for (const ImDrawVert& v : data->CmdLists[l]->VtxBuffer)
            if (v.pos.x < float(drawingWidth) - 0.5f) return true;
    return false;
}

VkImageLayout ViewerPanel::layoutBefore(const viewer::Swapchain& swapchain, uint32_t drawingWidth) const {
    return direct(swapchain, drawingWidth) ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
                                           : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
}

void ViewerPanel::ensureCache(VkFormat format, VkExtent2D extent) {
    if (cache_.image && cache_.extent.width == extent.width && cache_.extent.height == extent.height) return;
    if (cache_.image) VIEWER_CHECK(vkDeviceWaitIdle(gpu_.vk.device));  // an earlier frame may still copy from it
    vkDestroyFramebuffer(gpu_.vk.device, cacheFramebuffer_, nullptr);
    if (cache_.image) viewer::destroyImage(gpu_, cache_);
    cache_ = viewer::createImage(gpu_, extent, format,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = cachePass_;
    info.attachmentCount = 1;
    info.pAttachments = &cache_.view;
    info.width = extent.width;
    info.height = extent.height;
    info.layers = 1;
    VIEWER_CHECK(vkCreateFramebuffer(gpu_.vk.device, &info, nullptr, &cacheFramebuffer_));
    cacheValid_ = false;
}

// Everything the panel's image depends on: the triangles, their clipping and texture, the display.
static void signature(const ImDrawData& data, std::vector<uint8_t>& out) {
    out.clear();
    auto put = [&out](const void* p, size_t bytes) {
        out.insert(out.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + bytes);
    };
    put(&data.DisplayPos, sizeof data.DisplayPos);
    put(&data.DisplaySize, sizeof data.DisplaySize);
    for (int l = 0; l < data.CmdListsCount; ++l) {
        const ImDrawList& list = *data.CmdLists[l];
        put(list.VtxBuffer.Data, size_t(list.VtxBuffer.Size) * sizeof(ImDrawVert));
        put(list.IdxBuffer.Data, size_t(list.IdxBuffer.Size) * sizeof(ImDrawIdx));
        for (const ImDrawCmd& c : list.CmdBuffer) {
            put(&c.ClipRect, sizeof c.ClipRect);
            put(&c.TextureId, sizeof c.TextureId);
            put(&c.VtxOffset, sizeof c.VtxOffset);
            put(&c.IdxOffset, sizeof c.IdxOffset);
            put(&c.ElemCount, sizeof c.ElemCount);
        }
    }
}

bool ViewerPanel::wantsMouse() const { return shown_ && built_ && ImGui::GetIO().WantCaptureMouse; }
bool ViewerPanel::wantsKeyboard() const { return shown_ && built_ && ImGui::GetIO().WantCaptureKeyboard; }

PanelActions ViewerPanel::build(Options& o, inkwell::Camera& camera, const PanelInfo& info) {
    PanelActions a;
    // ImGui makes every frame's triangles anew; most frames nothing in the panel changed (a cursor blinks in an
    // edited field, hence its exception; and once a second the panel is made anyway).
    const double now = glfwGetTime();
    if (built_ && framesToBuild_ == 0 && info == builtInfo_ && !ImGui::GetIO().WantTextInput && now - builtAt_ < 1.0)
        return a;
    framesToBuild_ = std::max(0, framesToBuild_ - 1);
    builtInfo_ = info;
    builtAt_ = now;
    fresh_ = true;
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    built_ = true;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(float(info.drawing.width), 0));
    ImGui::SetNextWindowSize(ImVec2(display.x - float(info.drawing.width), display.y));
    ImGui::Begin("inkwell", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoBringToFrontOnFocus);
    ImGui::PushItemWidth(-130);  // the labels' room on the right

    ImGui::TextUnformatted(info.model.c_str());
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 20);
    if (ImGui::Button("?")) help_ = !help_;
    ImGui::Text("%zu control points, %llu points", info.controlPoints, (unsigned long long)info.points);
    ImGui::Text("%.1f ms a frame, drawing %u x %u", info.frameMs, info.drawing.width, info.drawing.height);
    if (info.refining) {
        char text[64];
        if (std::string(info.task) == "refining") {
            std::snprintf(text, sizeof text, "refining %d%%", int(100 * info.refineProgress));
            ImGui::ProgressBar(float(info.refineProgress), ImVec2(-1, 0), text);
        } else {  // the tracing says nothing of its progress: a bar that runs along
            ImGui::ProgressBar(float(std::fmod(ImGui::GetTime() / 2.0, 1.0)), ImVec2(-1, 0), info.task);
        }
    }

    inkwell::Look& s = o.look;
    inkwell::DrawingOptions& d = o.drawing;
    if (ImGui::CollapsingHeader("Style", ImGuiTreeNodeFlags_DefaultOpen)) {
        // The style's parts: the dots (none: the stipple set only gives the lines their depth) and the pen lines.
        int dots = s.dots ? int(d.style) + 1 : 0;
        if (ImGui::Combo("dots", &dots, "none\0stipple\0direction\0both\0")) {
            s.dots = dots > 0;
            const inkwell::Style style = dots > 0 ? inkwell::Style(dots - 1) : inkwell::Style::Stipple;
            a.rerefine = style != d.style;
            d.style = style;
            a.restyle = true;
        }
        bool contours = d.contours, hatching = d.hatching;
        a.rerefine |= ImGui::Checkbox("contours", &contours);
        ImGui::SameLine();
        a.rerefine |= ImGui::Checkbox("hatching", &hatching);
        if (contours != d.contours || hatching != d.hatching) {
            d.contours = contours;
            d.hatching = hatching;
            if (!s.dots &&
                !(d.contours || d.hatching || d.creases || d.boundaries)) {  // something is drawn: the stipples back
                s.dots = true;
                a.restyle = true;
            }
        }
        if (d.hatching) {
            a.rerefine |= sliderOnRelease("hatch spacing", d.hatchSpacing, kHatchSpacingSpan.lo, kHatchSpacingSpan.hi,
                                          "%.4f", spacingEdit_);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("of the finest hatching, a fraction of the diagonal");
            int families = int(d.hatchFamilies);
            ImGui::RadioButton("one family", &families, 1);
            ImGui::SameLine();
            ImGui::RadioButton("crossed", &families, 2);
            ImGui::SameLine();
            ImGui::RadioButton("+ diagonal", &families, 3);
            if (uint32_t(families) != d.hatchFamilies) {
                d.hatchFamilies = uint32_t(families);
                a.rerefine = true;
            }
        }
        a.rerefine |= sliderOnRelease("levels", d.levels, 0, 8, levelsEdit_);
        if (d.style != inkwell::Style::Direction) {
            int distribution = d.distribution == inkwell::Distribution::BlueNoise ? 0 : 1;
            if (ImGui::Combo("stipples", &distribution, "blue noise\0refinement\0")) {
                d.distribution =
                    distribution == 0 ? inkwell::Distribution::BlueNoise : inkwell::Distribution::Refinement;
                a.rerefine = true;
            }
        }
        if (d.style != inkwell::Style::Stipple) {
            int direction = int(d.direction);
            if (ImGui::Combo("direction", &direction, "axis\0curvature-min\0curvature-max\0")) {
                d.direction = inkwell::DirectionField(direction);
                a.rerefine = true;
            }
        }
        a.rerefine |= sliderOnRelease("passes", d.passes, 0, 8, passesEdit_);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("independent sets of level-1 children; 0: the default");
    }
    if (ImGui::CollapsingHeader("Drawing", ImGuiTreeNodeFlags_DefaultOpen)) {
        bool changed = false;
        bool tone = s.toneGamma > 0;
        if (ImGui::Checkbox("tone", &tone)) {
            if (!tone) toneGamma_ = s.toneGamma;
            s.toneGamma = tone ? toneGamma_ : 0.0f;
            changed = true;
        }
        if (tone) {
            changed |= ImGui::SliderFloat("tone curve (gamma)", &s.toneGamma, kToneSpan.lo, kToneSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
            changed |= ImGui::SliderFloat("ink density", &s.inkDensity, kInkDensitySpan.lo, kInkDensitySpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
        }
        if (s.dots) {  // the dots' own settings
            changed |= ImGui::SliderFloat("dot size (px)", &s.dotSize, kDotSpan.lo, kDotSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
            changed |= ImGui::SliderFloat("silhouette (px)", &s.silhouetteSize, kDotSpan.lo, kDotSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
            changed |= ImGui::SliderFloat("tau (silhouette)", &s.tau, kTauSpan.lo, kTauSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
        }
        if (d.contours) {
            changed |= ImGui::SliderFloat("contour pen (px)", &s.penWidth, kContourPenSpan.lo, kContourPenSpan.hi,
                                          "%.2f", ImGuiSliderFlags_AlwaysClamp);
            changed |= ImGui::SliderFloat("halo (px)", &s.halo, kHaloSpan.lo, kHaloSpan.hi, "%.1f",
                                          ImGuiSliderFlags_AlwaysClamp);
        }
        if (d.hatching)
            changed |= ImGui::SliderFloat("hatch pen (px)", &s.hatchWidth, kFinePenSpan.lo, kFinePenSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
        changed |= ImGui::Checkbox("hidden lines", &s.hiddenLines);
        ImGui::SameLine();
        changed |= ImGui::Checkbox("occlusion", &s.occlusion);
        if (s.dots && s.toneGamma > 0.0f) {
            ImGui::SameLine();
            changed |= ImGui::Checkbox("spacing", &s.screenSpacing);
        }
        if (s.hiddenLines) {
            if (s.dots)
                changed |= ImGui::SliderFloat("hidden dots (px)", &s.hiddenDotSize, kHiddenDotSpan.lo,
                                              kHiddenDotSpan.hi, "%.2f", ImGuiSliderFlags_AlwaysClamp);
            if (d.contours)
                changed |= ImGui::SliderFloat("hidden pen (px)", &s.hiddenPenWidth, kFinePenSpan.lo, kFinePenSpan.hi,
                                              "%.2f", ImGuiSliderFlags_AlwaysClamp);
            changed |= ImGui::SliderFloat("hidden ink", &s.hiddenOpacity, kHiddenInkSpan.lo, kHiddenInkSpan.hi, "%.2f",
                                          ImGuiSliderFlags_AlwaysClamp);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("how much of the ink the hidden lines take (opacity)");
        }
        // The light as two angles: around the view axis from straight ahead, and up from the horizon.
        const float length = std::hypot(s.light[0], s.light[1], s.light[2]);
        constexpr float kDegrees = 57.29577951308232f;
        float azimuth = kDegrees * std::atan2(s.light[0], s.light[2]),
              elevation = kDegrees * std::asin(std::clamp(s.light[1] / length, -1.0f, 1.0f));
        bool light = ImGui::SliderFloat("light azimuth", &azimuth, -180.0f, 180.0f, "%.0f deg");
        light |= ImGui::SliderFloat("light elevation", &elevation, -90.0f, 90.0f, "%.0f deg");
        if (light) {
            const float az = azimuth / kDegrees, el = elevation / kDegrees;
            s.light = {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
            changed = true;
        }
        changed |= ImGui::Checkbox("light follows the camera", &s.lightFollowsCamera);
        const ImGuiColorEditFlags colour = ImGuiColorEditFlags_DisplayHex | ImGuiColorEditFlags_NoOptions;
        changed |= ImGui::ColorEdit3("ink", s.ink.data(), colour);  // the hidden lines' ink follows it
        changed |= ImGui::ColorEdit3("paper", s.paper.data(), colour);
        a.restyle |= changed;
    }
    if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
        int mode = camera.freeOrbit ? 1 : 0;
        ImGui::RadioButton("turntable", &mode, 0);
        ImGui::SameLine();
        ImGui::RadioButton("free", &mode, 1);
        ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 70);
        if (ImGui::Button("reset (R)")) a.resetCamera = true;
        if ((mode == 1) != camera.freeOrbit) {
            camera.freeOrbit = mode == 1;
            if (!camera.freeOrbit) {  // back onto the turntable: the nearest view with the up axis up
                float e = std::remainder(camera.elevationDeg, 360.0f);
                if (std::abs(e) > 90) {
                    e = std::copysign(180.0f, e) - e;
                    camera.azimuthDeg += 180;
                }
                camera.elevationDeg = std::clamp(e, -89.0f, 89.0f);
            }
        }
        // With `--up auto` at the start, the first entry returns to what it found, and to its first picture.
        const int offset = info.autoUp ? 1 : 0;
        const std::string names =
            (info.autoUp ? "auto (" + std::string(info.autoUp) + ")" + std::string(1, '\0') : "") +
            std::string(kUpNames, sizeof(kUpNames) - 1);
        int up = o.autoUp && info.autoUp
                     ? 0
                     : offset + int(std::find(std::begin(kUpOrder), std::end(kUpOrder), o.up) - std::begin(kUpOrder));
        if (ImGui::Combo("up axis", &up, names.c_str())) {
            if (up < offset) {
                a.upAuto = a.restyle = true;
            } else {
                o.up = kUpOrder[up - offset];
                a.upChanged = a.restyle = true;
            }
        }
        ImGui::SliderFloat("field of view", &camera.fovyDeg, 10.0f, 100.0f, "%.0f deg", ImGuiSliderFlags_AlwaysClamp);
        ImGui::DragFloat("azimuth", &camera.azimuthDeg, 0.5f, 0, 0, "%.1f deg");
        if (camera.freeOrbit)
            ImGui::DragFloat("elevation", &camera.elevationDeg, 0.5f, 0, 0, "%.1f deg");
        else
            ImGui::DragFloat("elevation", &camera.elevationDeg, 0.5f, -89.0f, 89.0f, "%.1f deg",
                             ImGuiSliderFlags_AlwaysClamp);
        ImGui::DragFloat("distance", &camera.distance, 0.01f, 0.1f, 50.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
        if (ImGui::Button("copy camera")) a.copyCamera = true;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the camera as JSON on the clipboard (ctrl + C)");
        ImGui::SameLine();
        if (ImGui::Button("paste camera")) a.pasteCamera = true;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the clipboard's camera: JSON or --camera options (ctrl + V)");
        ImGui::SameLine();
        if (ImGui::Button("as options")) {
            char text[160];
            std::snprintf(text, sizeof text, "--camera %.2f %.2f %.3f --up %s", camera.azimuthDeg, camera.elevationDeg,
                          camera.distance, inkwell::upName(o.up));
            ImGui::SetClipboardText(text);
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("--camera AZ EL DIST --up AXIS on the clipboard, for render");
    }
    if (ImGui::CollapsingHeader("Save", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (pngPath_.empty() && !ImGui::IsAnyItemActive()) pngPath_ = info.pngPath;
        if (pngSize_[0] == 0) {
            pngSize_[0] = int(info.drawing.width);
            pngSize_[1] = int(info.drawing.height);
        }
        ImGui::InputText("file", &pngPath_);
        ImGui::InputInt2("size (px)", pngSize_);
        pngSize_[0] = std::clamp(pngSize_[0], 1, 8192);
        pngSize_[1] = std::clamp(pngSize_[1], 1, 8192);
        ImGui::BeginDisabled(info.refining || pngPath_.empty());
        // The file's name with the button's extension: a PNG, or the marks on a page (--page, --pen-width, ...).
        for (const char* type : {"PNG", "SVG", "PDF"}) {
            if (type[1] != 'N') ImGui::SameLine();
            if (ImGui::Button(type[1] == 'N' ? "save PNG" : type)) {
                std::string extension = std::string(".") + type;
                for (char& c : extension) c = char(std::tolower(c));
                pngPath_ = std::filesystem::path(pngPath_).replace_extension(extension).string();
                a.savePng = true;
                a.pngPath = pngPath_;
                a.pngSize[0] = uint32_t(pngSize_[0]);
                a.pngSize[1] = uint32_t(pngSize_[1]);
            }
        }
        ImGui::EndDisabled();
        ImGui::SameLine();
        if (ImGui::Button("screenshot (S)")) a.saveScreenshot = true;
        ImGui::InputText("preset", &presetPath_);
        ImGui::BeginDisabled(presetPath_.empty());
        if (ImGui::Button("load preset")) a.loadPreset = true;
        ImGui::SameLine();
        if (ImGui::Button("save preset")) a.savePreset = true;
        ImGui::EndDisabled();
        a.presetPath = presetPath_;
    }
    // A mesh's feature lines, each on its own pen (docs/lines.md): last and closed at first, so that the sections
    // above keep their places. The switches set --creases and --boundaries.
    if (ImGui::CollapsingHeader("Creases and boundaries")) {
        bool creases = d.creases, boundaries = d.boundaries;
        a.rerefine |= ImGui::Checkbox("creases", &creases);
        ImGui::SameLine();
        a.rerefine |= ImGui::Checkbox("boundaries", &boundaries);
        if (creases != d.creases || boundaries != d.boundaries) {
            d.creases = creases;
            d.boundaries = boundaries;
            o.creases = creases ? "on" : "off";
            o.boundaries = boundaries ? "on" : "off";
        }
        a.restyle |= ImGui::SliderFloat("crease pen (px)", &s.creaseWidth, kContourPenSpan.lo, kContourPenSpan.hi,
                                        "%.2f", ImGuiSliderFlags_AlwaysClamp);
        a.restyle |= ImGui::SliderFloat("boundary pen (px)", &s.boundaryWidth, kContourPenSpan.lo, kContourPenSpan.hi,
                                        "%.2f", ImGuiSliderFlags_AlwaysClamp);
    }
    if (!info.message.empty()) {
        ImGui::Separator();
        ImGui::TextWrapped("%s", info.message.c_str());
    }
    ImGui::PopItemWidth();
    ImGui::End();

    if (help_) {
        ImGui::SetNextWindowPos(ImVec2(float(info.drawing.width) / 2, display.y / 2), ImGuiCond_Always,
                                ImVec2(0.5f, 0.5f));
        ImGui::Begin(
            "Mouse and keys", &help_,
            ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
        if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
            for (const auto& row : kHelp) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(row[0]);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(row[1]);
            }
            ImGui::EndTable();
        }
        ImGui::Text("S saves to %s", info.screenshotPath.c_str());
        ImGui::End();
    }
    ImGui::Render();
    return a;
}

void ViewerPanel::record(VkCommandBuffer cmd, const viewer::Swapchain& swapchain, uint32_t index,
                         uint32_t drawingWidth) {
    ImDrawData* data = ImGui::GetDrawData();  // the last built frame's
    if (!direct(swapchain, drawingWidth)) {
        const VkExtent2D extent{swapchain.extent.width - drawingWidth, swapchain.extent.height};
        ensureCache(swapchain.format, extent);
        if (fresh_ && data && data->Valid) signature(*data, drawn_);
        if (!cacheValid_ || (fresh_ && drawn_ != signature_)) {
            const ImVec4 bg = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
            VkClearValue clear{};
            clear.color = {{bg.x, bg.y, bg.z, 1.0f}};
            VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            begin.renderPass = cachePass_;
            begin.framebuffer = cacheFramebuffer_;
            begin.renderArea = {{0, 0}, extent};
            begin.clearValueCount = 1;
            begin.pClearValues = &clear;
            vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
            if (data && data->Valid) {
                // The panel's part of the display, mapped onto its image.
                const ImVec2 pos = data->DisplayPos, size = data->DisplaySize;
                data->DisplayPos.x += float(drawingWidth);
                data->DisplaySize.x = float(extent.width);
                ImGui_ImplVulkan_RenderDrawData(data, cmd);
                data->DisplayPos = pos;
                data->DisplaySize = size;
            }
            vkCmdEndRenderPass(cmd);
            signature_.swap(drawn_);
            cacheValid_ = true;
        }
        fresh_ = false;
        VkImageCopy region{};
        region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.dstSubresource = region.srcSubresource;
        region.dstOffset = {int32_t(drawingWidth), 0, 0};
        region.extent = {extent.width, extent.height, 1};
        vkCmdCopyImage(cmd, cache_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, swapchain.images.at(index),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        // Presentation waits on the submission's semaphore.
        viewer::imageBarrier(cmd, swapchain.images.at(index), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_COPY_BIT,
                             VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, 0);
        return;
    }
    cacheValid_ = false;  // drawn again once the popup is gone
    if (framebuffers_.empty())
        for (VkImageView view : swapchain.views) {
            VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            info.renderPass = renderPass_;
            info.attachmentCount = 1;
            info.pAttachments = &view;
            info.width = swapchain.extent.width;
            info.height = swapchain.extent.height;
            info.layers = 1;
            VkFramebuffer framebuffer;
            VIEWER_CHECK(vkCreateFramebuffer(gpu_.vk.device, &info, nullptr, &framebuffer));
            framebuffers_.push_back(framebuffer);
        }
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = renderPass_;
    begin.framebuffer = framebuffers_.at(index);
    begin.renderArea = {{0, 0}, swapchain.extent};
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    // The panel's side of the image was not drawn (its contents are undefined): its background first.
    if (drawingWidth < swapchain.extent.width) {
        const ImVec4 bg = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
        VkClearAttachment clear{VK_IMAGE_ASPECT_COLOR_BIT, 0, {}};
        clear.clearValue.color = {{bg.x, bg.y, bg.z, 1.0f}};
        VkClearRect rect{
            {{int32_t(drawingWidth), 0}, {swapchain.extent.width - drawingWidth, swapchain.extent.height}}, 0, 1};
        vkCmdClearAttachments(cmd, 1, &clear, 1, &rect);
    }
    if (data && data->Valid) ImGui_ImplVulkan_RenderDrawData(data, cmd);
    vkCmdEndRenderPass(cmd);
}

}  // namespace app
