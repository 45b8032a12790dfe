// Pen lines on the device (docs/lines.md): the traced strokes (lines.h) as segments fixed in object space, and
// the per-frame passes that draw them. lines.comp decides per segment what shows — against the splat depth grid
// the dots' pass built, and by tone for hatching — into a draw list; line.vert/line.frag draw the list as
// antialiased capsules in one graphics pass: hatching, hidden contours, the halos of interior contours (paper),
// then the visible contours.
#pragma once

#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "lines/lines.h"
#include "shared/lines.h"

#include <glm/glm.hpp>
#include <vector>

namespace ink {

struct RenderStyle;

// The strokes of a drawing on the device: hatching, creases and boundaries (fixed for the model) and contours
// (traced for a view, and replaced when the view changes). Each replacement waits for the device to be idle.
class StrokeBuffers {
public:
    explicit StrokeBuffers(Context& ctx);  // both empty
    ~StrokeBuffers();
    StrokeBuffers(const StrokeBuffers&) = delete;
    StrokeBuffers& operator=(const StrokeBuffers&) = delete;

    enum Kind { Contours = 0, Hatching = 1, Creases = 2, Boundaries = 3 };
    static constexpr int kKinds = 4;
    void set(Kind kind, const std::vector<PenStroke>& strokes);

    struct Segments {
        Buffer buffer;
        VkBufferView view = VK_NULL_HANDLE;
        uint32_t count = 0;
        uint32_t capacity = 0;
        uint64_t generation = 0;  // changes whenever buffer or count change
    };
    const Segments& segments(Kind kind) const { return segments_[kind]; }

private:
    void release();
    Context& ctx_;
    Segments segments_[kKinds];
};

// A segment that showed in a frame (tests, statistics): its ends in pixels, whether it was visible, hidden or an
// interior contour (gpu::SEG_* bits), and its index among the traced segments (segmentTexels order). The device
// writes gpu::DrawSegment (spirv_shaders/shared/lines.h).
struct DrawnSegment {
    glm::vec2 a, b;
    glm::vec2 halfWidths;  // pixels
    uint32_t flags;
    uint32_t segment;
};
constexpr uint32_t kSegmentVisible = gpu::SEG_VISIBLE, kSegmentHidden = gpu::SEG_HIDDEN,
                   kSegmentInterior = gpu::SEG_INTERIOR;

// The per-frame side, owned by PointRenderer.
class LineRenderer {
public:
    // `twoSided`: the strokes lie on a surface that may be open, whose hatching shows where it faces away too.
    LineRenderer(Context& ctx, const StrokeBuffers& strokes, VkFormat colorFormat, uint32_t framesInFlight,
                 bool twoSided = false);
    ~LineRenderer();
    LineRenderer(const LineRenderer&) = delete;
    LineRenderer& operator=(const LineRenderer&) = delete;

    void setStyle(VkCommandBuffer cmd, const RenderStyle& style, float pixelScale);
    // Host side, before recording frame `frame`: (re)binds its lists to the strokes and the frame's depth grid,
    // coverage and drawn bounds (render_common.glsl), waiting for the device when they changed.
    void sync(uint32_t frame, const Buffer& depth, const Buffer& coverage, const Buffer& drawn);
    // In the transfer phase of the frame (after the barrier that follows its previous use): empties its lists.
    void recordReset(VkCommandBuffer cmd, uint32_t frame);
    // After the depth grid is complete: lines.comp over every segment. `pushBack` in model units.
    void recordCull(VkCommandBuffer cmd, const glm::mat4& view, const glm::vec4& projection, VkExtent2D extent,
                    float pushBack, uint32_t frame);
    // Whether this style stamps the lines in compute (recordStamp) rather than drawing quads (recordDraw).
    bool stamps() const { return stamps_; }
    // After recordCull, behind a compute barrier: lines_stamp.comp into the coverage (stamps() only).
    void recordStamp(VkCommandBuffer cmd, uint32_t frame);
    // Inside the rendering pass, after the dots (nothing when stamps()).
    void recordDraw(VkCommandBuffer cmd, VkExtent2D extent, uint32_t frame) const;
    // The segments of `kind` frame `frame` drew last, in the order of the traced segments (waits for the device).
    std::vector<DrawnSegment> drawn(StrokeBuffers::Kind kind, uint32_t frame = 0) const;

private:
    using Push = gpu::LineCamera;  // the push constants (spirv_shaders/shared/lines.h)
    struct List {
        Buffer buffer;
        DescriptorSet descriptors;
        uint64_t generation = ~uint64_t(0);
        VkBuffer depth = VK_NULL_HANDLE, coverage = VK_NULL_HANDLE;
    };
    struct Frame {
        List lists[StrokeBuffers::kKinds];
        Push push{};
    };
    void release();

    Context& ctx_;
    const StrokeBuffers& strokes_;
    bool twoSided_ = false;
    std::vector<Frame> frames_;
    Buffer styleBuffer_;
    float pixelScale_ = 1.0f;
    bool cpuDriver_ = false;  // lavapipe: stamps by default
    bool stamps_ = false;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;  // a throwaway set's, for the pipeline layout
    DescriptorSet layoutSet_;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline cull_ = VK_NULL_HANDLE, runs_ = VK_NULL_HANDLE, stamp_ = VK_NULL_HANDLE, draw_ = VK_NULL_HANDLE,
               halo_ = VK_NULL_HANDLE;
};

// Segments of strokes of one kind as the device reads them: three RGBA32F texels each (lines_common.glsl).
// Hatching strokes taper over their last `taper` (model units) at both ends.
std::vector<float> segmentTexels(const std::vector<PenStroke>& strokes, StrokeBuffers::Kind kind);
// The stroke each segment of segmentTexels belongs to.
std::vector<uint32_t> segmentStrokes(const std::vector<PenStroke>& strokes);

}  // namespace ink
