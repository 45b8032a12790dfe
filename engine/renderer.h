// Draws refined points as ink, straight from the refinement's device buffers (no readback). Per frame:
// splat.comp, over every point, splats oriented disks into a half-resolution depth grid and selects the dots
// that may show (the report's §5 class, tone, frustum) into a list; stamp.comp, over that list, tests them
// against the depth and stamps the visible ones into coverage bits, two a pixel; a graphics pipeline then inks
// the covered pixels (two triangles over their bounds). Most points never reach the stamping.
#pragma once

#include "camera.h"
#include "image.h"
#include "pipelines.h"
#include "refine.h"
#include "resources.h"

#include <glm/glm.hpp>
#include <vector>

namespace ink {

struct RenderStyle {
    glm::vec4 ink{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 paper{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 hiddenInk{0.0f, 0.0f, 0.0f, 0.45f};  // blended over the paper once: a grey line
    float frontSize = 2.0f;                        // dot diameter in output pixels
    float silhouetteSize = 2.4f;
    float hiddenSize = 1.4f;
    float tau = 0.1f;          // τ of the silhouette test (report §5)
    bool hiddenLines = false;  // draw occluded silhouettes faint
    bool occlusion = true;     // the splat depth pre-pass; off: every front-facing dot shows
    // Towards the light, in view space (x right, y up, z to the viewer) as seen from the default camera. The light
    // stays fixed to the model as the camera moves (so do the dots tone draws), unless it follows the camera.
    glm::vec3 light{-0.5f, 0.6f, 0.65f};
    bool lightFollowsCamera = false;
    // Tone: a front dot is drawn when its rank (PointRecord::tone: a selected stipple's rank, a refined point's
    // fixed random value) is below
    //   (ambient + (1 − max(0, n·l))^γ) · inkDensity · k,
    // k scaling the expected ink coverage of fully dark regions to about 60% at any zoom and point count.
    float toneGamma = 1.5f;  // 0: no tone, every front dot is drawn
    float inkDensity = 1.0f;
    float ambient = 0.04f;
    float splatScale = 2.0f;   // splat radius in units of the finest level's ρ
    uint32_t supersample = 2;  // offscreen: render this many times larger and filter down
};

// Matches `Style` in render_common.glsl (std140).
struct StyleBlock {
    glm::vec4 color[2];
    glm::vec4 size;
    glm::vec4 light;
    glm::vec4 tone;
    glm::vec4 options;
};

// Draws one or more refinements (e.g. stippling and direction sampling together) into a colour target.
class PointRenderer {
public:
    // `colorFormat` is that of the colour attachment draw() renders into (no depth attachment).
    PointRenderer(Context& ctx, std::vector<const GpuRefinement*> sets, VkFormat colorFormat);
    ~PointRenderer();
    PointRenderer(const PointRenderer&) = delete;
    PointRenderer& operator=(const PointRenderer&) = delete;

    // Records the style upload (outside rendering). `pixelScale` multiplies dot sizes (supersampling).
    void setStyle(VkCommandBuffer cmd, const RenderStyle& style, float pixelScale);
    // Records the visibility passes for this camera (outside rendering, before draw). Reallocates the depth
    // grid, after waiting for the device, when the extent changes.
    void prepare(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent);
    // Records the ink draws; call between vkCmdBeginRendering and vkCmdEndRendering, after prepare.
    void draw(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent) const;
    const RenderStyle& style() const { return style_; }

    // Milliseconds of the last frame's passes, from timestamps: splat (with the dot selection), stamp, and ink
    // (which ends at writeEnd).
    struct Timings {
        double splatMs = 0, stampMs = 0, inkMs = 0;
    };
    void writeEnd(VkCommandBuffer cmd) const;
    Timings timings() const;
    // Dots the last frame drew, over all sets (reads a counter back; waits for the device).
    uint32_t drawnDots() const;
    // The points of set `set` whose dots the last frame drew, as indices into its drawn points (reads the dot
    // list back; waits for the device).
    std::vector<uint32_t> drawnPoints(size_t set) const;

private:
    struct Set {
        Buffer dots;  // `DotList`: the dots that may show this frame, and stamp.comp's indirect dispatch
        VkBufferView texels = VK_NULL_HANDLE;  // the points as RGBA32F texels, 2 a point (vectorized loads)
        DescriptorSet descriptors;
        float splatRadius;
        uint32_t points;  // in the refinement's draw, read once at setup
        uint32_t first;   // its first point: not 0 when only the last level is kept
    };
    struct Push;
    Push push(const Set& set, const Camera& camera, VkExtent2D extent) const;
    void bindDescriptors();

    Context& ctx_;
    RenderStyle style_;
    float pixelScale_ = 1.0f;
    Buffer styleBuffer_, drawn_, depth_, coverage_;  // depth and coverage follow the target's extent
    VkExtent2D extent_{0, 0};
    std::vector<Set> sets_;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline splat_ = VK_NULL_HANDLE, stamp_ = VK_NULL_HANDLE, ink_ = VK_NULL_HANDLE;
    VkQueryPool timestamps_ = VK_NULL_HANDLE;
};

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

// Renders frames of the refinements at width × height (supersampled inside) and reads them back.
class OffscreenRenderer {
public:
    OffscreenRenderer(Context& ctx, uint32_t width, uint32_t height, const RenderStyle& style,
                      std::vector<const GpuRefinement*> sets);
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    void setStyle(const RenderStyle& style);
    RgbaImage render(const Camera& camera);
    // Draws a frame and waits for it, without reading it back (benchmarks).
    void draw(const Camera& camera);
    PointRenderer::Timings timings() const { return renderer_.timings(); }
    uint32_t drawnDots() const { return renderer_.drawnDots(); }
    std::vector<uint32_t> drawnPoints(size_t set) const { return renderer_.drawnPoints(set); }

private:
    void record(VkCommandBuffer cmd, const Camera& camera, bool readback);

    Context& ctx_;
    uint32_t factor_;
    Image color_;
    Buffer readback_;
    PointRenderer renderer_;
};

// Throws ink::Error when an offscreen image of width × height with this supersampling cannot be drawn on this
// device: a side beyond its image limit, or the splat depth grid beyond one storage buffer.
void checkOffscreenSize(const Context& ctx, uint32_t width, uint32_t height, uint32_t supersample);

}  // namespace ink
