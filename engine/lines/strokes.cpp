#include "lines/strokes.h"

#include "draw/render_style.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "line.frag.h"
#include "line.vert.h"
#include "lines.comp.h"
#include "lines_runs.comp.h"
#include "lines_stamp.comp.h"

namespace ink {

namespace {

constexpr VkShaderStageFlags kStages =
    VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
// The interface with lines.comp, lines_stamp.comp, line.vert and line.frag: spirv_shaders/shared/lines.h.
constexpr uint32_t kTexelsPerSegment = gpu::LINE_TEXELS;
constexpr VkDeviceSize kSegmentBytes = kTexelsPerSegment * 16;
constexpr VkDeviceSize kDrawListHeader = 16;  // the draw list's VkDrawIndirectCommand, then the segments
constexpr float kTaper = 0.02f;               // hatching tapers over this much at each end (model units)
// Hatching's tone is read from its normals averaged over this much of the stroke either side (model units): a stroke
// shows or not by the tone of the form it crosses, not by the ripples of the fit, which would cut it into dashes.
constexpr float kToneWindow = 0.015f;
using LineStyleBlock = gpu::LineStyle;

float floatOf(uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

}  // namespace

std::vector<float> segmentTexels(const std::vector<PenStroke>& strokes, StrokeBuffers::Kind strokeKind) {
    const bool hatching = strokeKind == StrokeBuffers::Hatching;
    const uint32_t feature = strokeKind == StrokeBuffers::Creases      ? gpu::KIND_CREASE
                             : strokeKind == StrokeBuffers::Boundaries ? gpu::KIND_BOUNDARY
                                                                       : 0u;
    std::vector<float> out;
    for (const PenStroke& s : strokes) {
        const size_t m = s.points.size();
        if (m < 2) continue;
        std::vector<float> arc(m, 0.0f);
        for (size_t i = 1; i < m; ++i) arc[i] = arc[i - 1] + (s.points[i] - s.points[i - 1]).norm();
        const float length = arc.back(), taper = std::min(kTaper, 0.3f * length);
        // The points' fourth texel: a feature line's standoff (PenStroke::standoff), else the pen's width factor,
        // which tapers a hatching stroke's open ends.
        auto fourth = [&](size_t i) {
            if (feature) return s.standoff.empty() ? 0.0f : s.standoff[i];
            if (!hatching || s.closed) return 1.0f;
            return 0.25f + 0.75f * std::min(1.0f, std::min(arc[i], length - arc[i]) / taper);
        };
        // Box-filtered normals along the stroke (prefix sums over arc length) for hatching's tone and facing.
        std::vector<Eigen::Vector3f> normals = s.normals;
        if (hatching && m > 2) {
            std::vector<Eigen::Vector3f> sum(m + 1, Eigen::Vector3f::Zero());
            for (size_t i = 0; i < m; ++i) sum[i + 1] = sum[i] + s.normals[i];
            size_t lo = 0, hi = 0;
            for (size_t i = 0; i < m; ++i) {
                while (arc[i] - arc[lo] > kToneWindow) ++lo;
                while (hi + 1 < m && arc[hi + 1] - arc[i] <= kToneWindow) ++hi;
                Eigen::Vector3f n = sum[hi + 1] - sum[lo];
                if (n.norm() > 1e-6f) normals[i] = n.normalized();
            }
        }
        const uint32_t kind0 =
            hatching ? gpu::KIND_HATCH | (s.family & 3u) << gpu::HATCH_FAMILY_SHIFT |
                           (s.level & 1u) << gpu::HATCH_LEVEL_SHIFT
                     : feature | (s.occluded ? gpu::KIND_OCCLUDED : 0u) | (s.faced ? gpu::KIND_FACED : 0u);
        const size_t segments = m - 1 + (s.closed ? 1 : 0);
        for (size_t i = 0; i < segments; ++i) {
            // The kind, and the segments before and after this one in its stroke (every kind: lines.comp walks them).
            const uint32_t kind = kind0 | uint32_t(std::min<size_t>(i, gpu::SEG_REACH)) << gpu::SEG_BEFORE_SHIFT |
                                  uint32_t(std::min<size_t>(segments - 1 - i, gpu::SEG_REACH)) << gpu::SEG_AFTER_SHIFT;
            size_t j = (i + 1) % m;
            // A crease's normal stays the mean of its faces' (PenStroke::normals): its length says how far they turn.
            const Eigen::Vector3f n = feature == gpu::KIND_CREASE
                                          ? Eigen::Vector3f(0.5f * (normals[i] + normals[j]))
                                          : Eigen::Vector3f((normals[i] + normals[j]).normalized());
            const float texels[12] = {s.points[i].x(), s.points[i].y(), s.points[i].z(), fourth(i),
                                      s.points[j].x(), s.points[j].y(), s.points[j].z(), fourth(j),
                                      n.x(),           n.y(),           n.z(),           floatOf(kind)};
            out.insert(out.end(), texels, texels + 12);
        }
    }
    return out;
}

std::vector<uint32_t> segmentStrokes(const std::vector<PenStroke>& strokes) {
    std::vector<uint32_t> out;
    for (uint32_t k = 0; k < strokes.size(); ++k) {
        const size_t m = strokes[k].points.size();
        if (m >= 2) out.insert(out.end(), m - 1 + (strokes[k].closed ? 1 : 0), k);
    }
    return out;
}

StrokeBuffers::StrokeBuffers(Context& ctx) : ctx_(ctx) {
    try {
        for (int kind = 0; kind < kKinds; ++kind) set(Kind(kind), {});
    } catch (...) {
        release();
        throw;
    }
}

StrokeBuffers::~StrokeBuffers() { release(); }

void StrokeBuffers::release() {
    for (Segments& s : segments_) {
        vkDestroyBufferView(ctx_.device, s.view, nullptr);
        destroyBuffer(ctx_, s.buffer);
    }
}

void StrokeBuffers::set(Kind kind, const std::vector<PenStroke>& strokes) {
    std::vector<float> texels = segmentTexels(strokes, kind);
    const uint32_t count = uint32_t(texels.size() / (4 * kTexelsPerSegment));
    Segments& s = segments_[kind];
    vkDeviceWaitIdle(ctx_.device);  // a frame in flight may read the old segments
    if (count > s.capacity || !s.buffer.buffer) {
        vkDestroyBufferView(ctx_.device, s.view, nullptr);
        s.view = VK_NULL_HANDLE;
        destroyBuffer(ctx_, s.buffer);
        s.capacity = std::max(count, 1024u);
        s.buffer = createBuffer(ctx_, s.capacity * kSegmentBytes,
                                VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                MemoryUse::Device);
        VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        info.buffer = s.buffer.buffer;
        info.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        info.range = VK_WHOLE_SIZE;
        VK_CHECK(vkCreateBufferView(ctx_.device, &info, nullptr, &s.view));
    }
    uploadBuffer(ctx_, s.buffer, texels.data(), texels.size() * sizeof(float));
    s.count = count;
    ++s.generation;
}

LineRenderer::LineRenderer(Context& ctx, const StrokeBuffers& strokes, VkFormat colorFormat, uint32_t framesInFlight,
                           bool twoSided)
    : ctx_(ctx), strokes_(strokes), twoSided_(twoSided), frames_(std::max(1u, framesInFlight)) {
    try {
        styleBuffer_ =
            createBuffer(ctx, sizeof(LineStyleBlock),
                         VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Device);
        // The set layout every frame's sets share (created alike, hence compatible).
        cpuDriver_ = ctx.driverId == VK_DRIVER_ID_MESA_LLVMPIPE;
        VkDescriptorSetLayoutBinding bindings[gpu::LINES_BINDINGS] = {
            {gpu::LINES_SEGMENTS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, kStages, nullptr},
            {gpu::LINES_DRAW_LIST, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kStages, nullptr},
            {gpu::LINES_STYLE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, kStages, nullptr},
            {gpu::LINES_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kStages, nullptr},
            {gpu::LINES_COVERAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kStages, nullptr},
            {gpu::LINES_DRAWN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kStages, nullptr}};
        VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        info.bindingCount = gpu::LINES_BINDINGS;
        info.pBindings = bindings;
        VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &info, nullptr, &setLayout_));
        layout_ = createPipelineLayout(ctx, setLayout_, sizeof(Push), kStages);
        cull_ = createComputePipeline(ctx, layout_, spv_lines_comp);
        runs_ = createComputePipeline(ctx, layout_, spv_lines_runs_comp);
        stamp_ = createComputePipeline(ctx, layout_, spv_lines_stamp_comp);
        // Ink takes the darker of the line and the target, a halo's paper the lighter: a pixel that several
        // segments of a stroke cover (their round ends overlap at every joint) is inked once, as stamping does.
        draw_ = createBlendedPipeline(ctx, layout_, colorFormat, spv_line_vert, spv_line_frag, VK_BLEND_OP_MIN);
        halo_ = createBlendedPipeline(ctx, layout_, colorFormat, spv_line_vert, spv_line_frag, VK_BLEND_OP_MAX);
    } catch (...) {
        release();
        throw;
    }
}

LineRenderer::~LineRenderer() { release(); }

void LineRenderer::release() {
    for (Frame& f : frames_)
        for (List& l : f.lists) {
            destroyDescriptorSet(ctx_, l.descriptors);
            destroyBuffer(ctx_, l.buffer);
        }
    frames_.clear();
    vkDestroyPipeline(ctx_.device, cull_, nullptr);
    vkDestroyPipeline(ctx_.device, stamp_, nullptr);
    vkDestroyPipeline(ctx_.device, runs_, nullptr);
    vkDestroyPipeline(ctx_.device, draw_, nullptr);
    vkDestroyPipeline(ctx_.device, halo_, nullptr);
    vkDestroyPipelineLayout(ctx_.device, layout_, nullptr);
    vkDestroyDescriptorSetLayout(ctx_.device, setLayout_, nullptr);
    destroyBuffer(ctx_, styleBuffer_);
    cull_ = runs_ = stamp_ = draw_ = halo_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    setLayout_ = VK_NULL_HANDLE;
}

void LineRenderer::setStyle(VkCommandBuffer cmd, const RenderStyle& s, float pixelScale) {
    pixelScale_ = pixelScale;
    stamps_ = s.lineRaster == RenderStyle::LineRaster::Stamps ||
              (s.lineRaster == RenderStyle::LineRaster::Auto && cpuDriver_);
    LineStyleBlock b{};
    b.ink = s.ink;
    b.hiddenInk = s.hiddenInk;
    b.paper = s.paper;
    b.widths = glm::vec4(s.penWidth, s.hiddenPenWidth, s.hatchWidth, s.haloWidth) * pixelScale;
    b.thresholds = s.hatchThresholds;
    b.diagonal = glm::vec4(s.diagonalThresholds, s.diagonalMinFacing, 0.0f);
    b.light = glm::vec4(shaderLight(s), s.toneGamma);
    b.tone = glm::vec4(s.inkDensity, s.ambient, s.hatchMinFacing, s.hatchMinRun);
    b.options = glm::vec4(s.lightFollowsCamera ? 0.0f : 1.0f, s.hiddenLines ? 1.0f : 0.0f, 0.0f, 0.0f);
    b.features = glm::vec4(glm::vec2(s.creaseWidth, s.boundaryWidth) * pixelScale, s.lineMinRun, 0.0f);
    recordUniformUpdate(cmd, styleBuffer_, &b, sizeof(b));
}

void LineRenderer::sync(uint32_t frame, const Buffer& depth, const Buffer& coverage, const Buffer& drawn) {
    Frame& f = frames_.at(frame);
    for (int kind = 0; kind < StrokeBuffers::kKinds; ++kind) {
        List& l = f.lists[kind];
        const StrokeBuffers::Segments& s = strokes_.segments(StrokeBuffers::Kind(kind));
        if (l.generation == s.generation && l.depth == depth.buffer && l.coverage == coverage.buffer) continue;
        vkDeviceWaitIdle(ctx_.device);  // this frame slot's last use may still read the list and its set
        const VkDeviceSize bytes = kDrawListHeader + sizeof(gpu::DrawSegment) * std::max(1u, s.capacity);
        if (!l.buffer.buffer || l.buffer.size < bytes) {
            destroyBuffer(ctx_, l.buffer);
            l.buffer = createBuffer(ctx_, bytes,
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                        VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                    MemoryUse::Device);
        }
        destroyDescriptorSet(ctx_, l.descriptors);
        l.descriptors = createDescriptorSet(
            ctx_,
            {{gpu::LINES_SEGMENTS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_NULL_HANDLE, 1, 0, 0, s.view},
             {gpu::LINES_DRAW_LIST, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, l.buffer.buffer},
             {gpu::LINES_STYLE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, styleBuffer_.buffer},
             {gpu::LINES_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, depth.buffer},
             {gpu::LINES_COVERAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, coverage.buffer},
             {gpu::LINES_DRAWN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, drawn.buffer}},
            kStages);
        l.generation = s.generation;
        l.depth = depth.buffer;
        l.coverage = coverage.buffer;
    }
}

void LineRenderer::recordReset(VkCommandBuffer cmd, uint32_t frame) {
    const uint32_t empty[4] = {0, 1, 0, 0};  // VkDrawIndirectCommand: no vertices
    for (List& l : frames_.at(frame).lists) vkCmdUpdateBuffer(cmd, l.buffer.buffer, 0, sizeof(empty), empty);
}

void LineRenderer::recordCull(VkCommandBuffer cmd, const glm::mat4& view, const glm::vec4& projection,
                              VkExtent2D extent, float pushBack, uint32_t frame) {
    Frame& f = frames_.at(frame);
    f.push =
        Push{view, projection, glm::vec4(extent.width, extent.height, (extent.width + 1) / 2, (extent.height + 1) / 2),
             glm::vec4(pushBack, pixelScale_, twoSided_ ? 1.0f : 0.0f, 0), glm::uvec4(0)};
    // One dispatch a kind of stroke, a thread a segment.
    auto dispatch = [&](VkPipeline pipeline, bool hatching) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        for (int kind = 0; kind < StrokeBuffers::kKinds; ++kind) {
            const uint32_t count = strokes_.segments(StrokeBuffers::Kind(kind)).count;
            if (count == 0 || (kind == StrokeBuffers::Hatching && !hatching)) continue;
            Push p = f.push;
            p.counts = glm::uvec4(count, 0, 0, 0);
            vkCmdPushConstants(cmd, layout_, kStages, 0, sizeof(p), &p);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &f.lists[kind].descriptors.set,
                                    0, nullptr);
            vkCmdDispatch(cmd, (count + gpu::GROUP_SIZE - 1) / gpu::GROUP_SIZE, 1, 1);
        }
    };
    dispatch(cull_, true);
    // Contour, crease and boundary lines: the visibility of most of the stroke around each segment.
    stageBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    dispatch(runs_, false);
}

void LineRenderer::recordStamp(VkCommandBuffer cmd, uint32_t frame) {
    if (!stamps_) return;
    Frame& f = frames_.at(frame);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, stamp_);
    for (int kind = 0; kind < StrokeBuffers::kKinds; ++kind) {
        const uint32_t count = strokes_.segments(StrokeBuffers::Kind(kind)).count;
        if (count == 0) continue;
        Push p = f.push;
        p.counts = glm::uvec4(count, kind == StrokeBuffers::Hatching ? 0u : 1u, 0, 0);
        vkCmdPushConstants(cmd, layout_, kStages, 0, sizeof(p), &p);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &f.lists[kind].descriptors.set, 0,
                                nullptr);
        vkCmdDispatch(cmd, (count + gpu::GROUP_SIZE - 1) / gpu::GROUP_SIZE, 1, 1);  // at most every segment shows
    }
}

void LineRenderer::recordDraw(VkCommandBuffer cmd, VkExtent2D, uint32_t frame) const {
    if (stamps_) return;  // the ink pass inks the stamped coverage
    const Frame& f = frames_.at(frame);
    // Hatching, then hidden contours, creases and boundaries, the halos of interior contours and the visible
    // lines over them.
    const std::pair<int, uint32_t> passes[] = {{StrokeBuffers::Hatching, 0u},   {StrokeBuffers::Contours, 1u},
                                               {StrokeBuffers::Creases, 1u},    {StrokeBuffers::Boundaries, 1u},
                                               {StrokeBuffers::Contours, 2u},   {StrokeBuffers::Creases, 3u},
                                               {StrokeBuffers::Boundaries, 3u}, {StrokeBuffers::Contours, 3u}};
    for (auto [kind, mode] : passes) {
        if (strokes_.segments(StrokeBuffers::Kind(kind)).count == 0) continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mode == 2u ? halo_ : draw_);
        Push p = f.push;
        p.counts = glm::uvec4(0, mode, 0, 0);
        vkCmdPushConstants(cmd, layout_, kStages, 0, sizeof(p), &p);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &f.lists[kind].descriptors.set, 0,
                                nullptr);
        vkCmdDrawIndirect(cmd, f.lists[kind].buffer.buffer, 0, 1, 16);
    }
}

std::vector<DrawnSegment> LineRenderer::drawn(StrokeBuffers::Kind kind, uint32_t frame) const {
    vkDeviceWaitIdle(ctx_.device);
    const List& l = frames_.at(frame).lists[kind];
    uint32_t header[4] = {};
    downloadBuffer(ctx_, l.buffer, 0, header, sizeof(header));
    // A slot a segment; those that do not show have flags 0.
    std::vector<gpu::DrawSegment> raw(header[0] / 6);
    if (!raw.empty())
        downloadBuffer(ctx_, l.buffer, kDrawListHeader, raw.data(), raw.size() * sizeof(gpu::DrawSegment));
    std::vector<DrawnSegment> out;
    for (const gpu::DrawSegment& r : raw)
        if (r.flags != 0)
            out.push_back(
                {{r.ends.x, r.ends.y}, {r.ends.z, r.ends.w}, r.widths, r.flags, r.segment & gpu::SEG_INDEX_MASK});
    return out;
}

}  // namespace ink
