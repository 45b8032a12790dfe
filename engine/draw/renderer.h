// Draws refined points as ink, straight from the refinement's device buffers (no readback). Per frame:
// splat.comp, over every point, splats oriented disks into a half-resolution depth grid and selects the dots
// that may show (the report's §5 class, tone, frustum) into a list; stamp.comp, over that list, tests them
// against the depth and stamps the visible ones into coverage bits, two a pixel; a graphics pipeline then inks
// the covered pixels (two triangles over their bounds). Most points never reach the stamping.
#pragma once

#include "base/image.h"
#include "draw/camera.h"
#include "draw/render_style.h"
#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "lines/strokes.h"
#include "refine/refine.h"
#include "shared/render.h"
#include "vector/vector.h"

#include <glm/glm.hpp>
#include <memory>
#include <vector>

namespace ink {

using StyleBlock = gpu::DotStyle;  // the style uniform (spirv_shaders/shared/render.h)

// A colour image a frame is drawn into, the caller's or the offscreen renderer's: the public type
// (include/inkwell/inkwell.h). Its contents are discarded; it ends in `finalLayout`, visible to any later command.
using FrameTarget = inkwell::FrameTarget;

// Draws one or more refinements (e.g. stippling and direction sampling together) into a colour target. Each
// of `framesInFlight` frames owns its depth grid, coverage, dot lists and timestamps, so frame k + 1 can be
// recorded and run while frame k still runs; the caller passes which frame (0 .. framesInFlight − 1) and
// waits for that frame's previous use (its fence) before recording it again.
class PointRenderer {
public:
    // `colorFormat` is that of the colour attachment draw() renders into (no depth attachment).
    // `strokes`, when given, are drawn over the dots (and must outlive the renderer).
    PointRenderer(Context& ctx, std::vector<const GpuRefinement*> sets, VkFormat colorFormat,
                  uint32_t framesInFlight = 1, const StrokeBuffers* strokes = nullptr);
    ~PointRenderer();
    PointRenderer(const PointRenderer&) = delete;
    PointRenderer& operator=(const PointRenderer&) = delete;

    // Records the style upload (outside rendering), after every earlier read of the style. `pixelScale`
    // multiplies dot sizes (supersampling).
    void setStyle(VkCommandBuffer cmd, const RenderStyle& style, float pixelScale);
    // Records a whole frame into `target`: the visibility passes, the clear to paper, the ink, the end
    // timestamp; then, when `readback` is given, a copy of the image into it (host-visible, extent² × 4 bytes)
    // made visible to the host. What `render` and the viewer record.
    void recordFrame(VkCommandBuffer cmd, const Camera& camera, const FrameTarget& target, uint32_t frame = 0,
                     const Buffer* readback = nullptr);
    // The pieces of recordFrame, for a caller that renders more into the same pass. prepare records the
    // visibility passes (outside rendering, before draw); it reallocates the frame's depth grid, after waiting
    // for the device, when the extent changes. draw records the ink; call it between vkCmdBeginRendering and
    // vkCmdEndRendering, after prepare.
    void prepare(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame = 0);
    void draw(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame = 0) const;
    const RenderStyle& style() const { return style_; }
    uint32_t framesInFlight() const { return uint32_t(frames_.size()); }

    // Milliseconds of the last frame's passes, from timestamps: splat (with the dot selection), stamp, ink
    // (which ends at writeEnd), and between splat and stamp the occlusion test, the silhouettes' outline and reach
    // passes and the screen spacing.
    struct Timings {
        double splatMs = 0, stampMs = 0, inkMs = 0, spaceMs = 0;
    };
    void writeEnd(VkCommandBuffer cmd, uint32_t frame = 0) const;
    Timings timings(uint32_t frame = 0) const;
    // Dots frame `frame` drew last, over all sets (reads a counter back; waits for the device).
    uint32_t drawnDots(uint32_t frame = 0) const;
    // The points of set `set` whose dots frame `frame` drew last, as indices into its drawn points (reads the
    // dot list back; waits for the device).
    std::vector<uint32_t> drawnPoints(size_t set, uint32_t frame = 0) const;
    // Set `set`'s dot list of frame `frame` as stamp.comp left it (reads it back; waits for the device): every dot
    // that passed class, tone and frustum, its visible class, and its screen spacing state (shared/render.h).
    std::vector<gpu::Dot> dotList(size_t set, uint32_t frame = 0) const;
    // Set `set`'s shape operators (shape.comp), one a drawn point in the order of its points (reads them back).
    std::vector<gpu::vec4> shapes(size_t set) const;
    // The screen spacing's radius at darkness 1 and 1 / its grid's cell, target pixels; (0, 0) when off.
    glm::vec2 spacing() const { return spacing_; }
    // The marks frame `frame` drew, as vectors in its target's pixels (reads the dot lists back; waits for the
    // device): what stamp.comp decided, not decided again. A layer a set ("stipple", "direction") with its
    // visible silhouette and front dots, and the hidden silhouettes in a layer "hidden" below them; dots in
    // the order of their points, so the same frame gives the same marks.
    VectorDrawing vectorDrawing(uint32_t frame = 0) const;
    // The pen-line segments of `kind` frame `frame` drew last (waits for the device); none without strokes.
    std::vector<DrawnSegment> drawnSegments(StrokeBuffers::Kind kind, uint32_t frame = 0) const;

private:
    struct Set {
        VkBufferView texels = VK_NULL_HANDLE;  // the points as RGBA32F texels, 2 a point (vectorized loads)
        float splatRadius = 0;
        uint32_t points = 0;           // in the refinement's draw, read once at setup
        uint32_t first = 0;            // its first point: not 0 when only the last level is kept
        const char* name = "stipple";  // its vector layer's
        float area = 0;                // the surface's, normalized units (the selection's estimate); 0: unknown
        bool sparseSplats = false;     // its large disks sampled sparsely (gpu::CAMERA_SPARSE_SPLATS)
        bool twoSided = false;         // may be open (GpuRefinement::twoSided, gpu::CAMERA_TWO_SIDED)
        bool spaced = false;           // blue-noise stipples, spaced on the page with the style's screen spacing
                                       // (gpu::CAMERA_SPACED); not direction sampling's lines, nor the report's
                                       // random tone values
        Buffer shape;                  // each point's shape operator (shape.comp), a vec4 a point
        VkBufferView shapeTexels = VK_NULL_HANDLE;  // the same as RGBA32F texels
    };
    // What one frame in flight writes.
    struct Frame {
        Buffer drawn, depth, coverage;  // depth and coverage follow the target's extent
        Buffer spaceGrid;               // the screen spacing's grid (spacing.comp), spaceCells cells
        Buffer spaceOpen;               // its two lists of open dots, a word a point of the largest set
        uint32_t spaceCells = 0;
        VkExtent2D extent{0, 0};
        std::vector<Buffer> dots;                // a set's `DotList`: the dots that may show, and stamp.comp's dispatch
        std::vector<DescriptorSet> descriptors;  // a set's
        VkQueryPool timestamps = VK_NULL_HANDLE;
    };
    using Push = gpu::Camera;  // the push constants (spirv_shaders/shared/render.h)
    Push push(const Set& set, const Camera& camera, VkExtent2D extent) const;
    void bindDescriptors(Frame& frame);
    void release();

    Context& ctx_;
    RenderStyle style_;
    float pixelScale_ = 1.0f;
    glm::vec2 spacing_{0.0f};       // the screen spacing's radius at darkness 1 and 1 / its cell, target pixels
    glm::vec2 styleSpacing_{0.0f};  // the same as the style asks, before prepare() fits its grid to the target
    StyleBlock block_{};            // the style uniform as last written
    Buffer styleBuffer_;
    std::vector<Set> sets_;
    std::vector<Frame> frames_;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline splat_ = VK_NULL_HANDLE, stamp_ = VK_NULL_HANDLE, space_ = VK_NULL_HANDLE, ink_ = VK_NULL_HANDLE;
    std::unique_ptr<LineRenderer> lines_;
};

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

// Renders frames of the refinements at width × height (supersampled inside) and reads them back.
class OffscreenRenderer {
public:
    OffscreenRenderer(Context& ctx, uint32_t width, uint32_t height, const RenderStyle& style,
                      std::vector<const GpuRefinement*> sets, const StrokeBuffers* strokes = nullptr);
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
    // The dot list and the spacing, in the supersampled target's pixels (PointRenderer).
    std::vector<gpu::Dot> dotList(size_t set) const { return renderer_.dotList(set); }
    std::vector<gpu::vec4> shapes(size_t set) const { return renderer_.shapes(set); }
    glm::vec2 spacing() const { return renderer_.spacing(); }
    // The last frame's marks as vectors, in pixels of the requested width × height (renderer.vectorDrawing).
    VectorDrawing vectorDrawing() const;
    std::vector<DrawnSegment> drawnSegments(StrokeBuffers::Kind kind) const { return renderer_.drawnSegments(kind); }
    uint32_t supersample() const { return factor_; }

private:
    FrameTarget target() const;

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
