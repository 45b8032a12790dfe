#include "draw/renderer.h"

#include "base/common.h"
#include "select/select.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>

#include "ink.frag.h"
#include "ink.vert.h"
#include "shape.comp.h"
#include "shape_large.comp.h"
#include "spacing.comp.h"
#include "splat.comp.h"
#include "stamp.comp.h"

namespace ink {

namespace {

// The spacing the splats must cover: for stippling the finest level's ρ (the densest points); direction
// sampling makes lines about ρ₀ apart, so its splats must bridge the gaps between lines.
float splatSpacing(const GpuRefinement& r) {
    // Every candidate lies within R₀ of a selected stipple: disks of radius R₀ cover the surface the candidates do.
    if (r.selection) return float(0.5 * r.selection->plan.radius0);
    uint32_t last = r.plan.levelCount - 1;
    if (last == 0 || r.options.style == SampleStyle::Direction) return float(r.plan.rho0);
    return float(levelRho(r.plan, last));
}

constexpr VkShaderStageFlags kStages =
    VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
constexpr uint32_t kComputeGroup = gpu::GROUP_SIZE;
constexpr uint32_t kFarDepth = gpu::FAR_DEPTH;  // FLT_MAX: positive floats order as their bits do
constexpr uint32_t kTimestamps = 5;             // start, splat, visibility to spacing, stamp, ink
constexpr float kMaxDotPixels = 64.0f;          // dot diameters are clamped to this (times the pixel scale)
// The tone curve with screen spacing (docs/algorithm.md): at darkness d the dots are spread to an ink coverage of
// kCoverage·d (dots of area a, a density of kCoverage·d / a on the page), each kept at least its radius
// kSpaceRadius / √(density) from every other: with SPACE_SUPPLY ranked candidates a dot that leaves about the
// density asked for (random sequential adsorption, radius r: a maximal density of about 0.70 / r²; 0.72 centres
// the coverage of a torus of one tone on the asked, tests/gpu/test_page.cpp).
constexpr float kCoverage = 0.5f;
constexpr float kSpaceRadius = 0.72f;
// Candidates per dot asked for: the point set's own density on the screen is only estimated (its surface area
// over the projected area, n·v and depth), and the spacing needs more candidates than it keeps.
constexpr float kSupply = gpu::SPACE_SUPPLY;
// The screen spacing's radius at darkness 1 and its grid's cell (a side of at most the smallest radius over
// √2, so that a cell holds at most one accepted dot), in target pixels; (0, 0) without spacing.
glm::vec2 spacingRadius(const RenderStyle& s, float pixelScale) {
    if (!s.screenSpacing || s.toneGamma <= 0.0f || !s.drawDots) return glm::vec2(0.0f);
    float dotPixels = float(M_PI) * 0.25f * std::pow(s.frontSize * pixelScale, 2.0f);
    float maxDarkness = (s.ambient + 1.0f) * s.inkDensity;
    float radius = kSpaceRadius * std::sqrt(dotPixels / kCoverage);
    // At least √2 pixels at the darkest tone (overlapping dots): a cell at least a pixel.
    radius = std::max(radius, std::sqrt(2.0f * maxDarkness));
    float cell = radius / std::sqrt(maxDarkness) / std::sqrt(2.0f);
    return glm::vec2(radius, 1.0f / cell);
}
// The spacing grid's cells for a target: ceil(extent / cell) a side, as spacing.comp computes it.
uint32_t spacingCells(VkExtent2D extent, float inverseCell) {
    if (inverseCell <= 0.0f) return 1;
    return uint32_t(std::ceil(float(extent.width) * inverseCell)) *
           uint32_t(std::ceil(float(extent.height) * inverseCell));
}
// The spacing for a target whose grid (16 bytes a cell) must fit in maxBytes: on a very large target the cells
// grow, and with them the smallest radius (every radius scales: the darkest tones are spaced wider).
glm::vec2 fitSpacing(glm::vec2 spacing, float maxDarkness, VkExtent2D extent, VkDeviceSize maxBytes) {
    if (spacing.x <= 0.0f) return spacing;
    while (VkDeviceSize(spacingCells(extent, spacing.y)) * 16 > maxBytes) {
        spacing.y *= 0.97f;
        spacing.x = std::max(spacing.x, std::sqrt(2.0f * maxDarkness) / spacing.y);
    }
    return spacing;
}
// The spacing grid's size at most: the device's storage buffer range, and 256 MiB on any device.
VkDeviceSize spacingGridLimit(const Context& ctx) {
    return std::min<VkDeviceSize>(ctx.properties.limits.maxStorageBufferRange, VkDeviceSize(256) << 20);
}
// The splat depth grid, a float for every 2×2 pixels, is one storage-buffer binding; coverage is smaller.
VkDeviceSize depthGridBytes(VkExtent2D extent) {
    return VkDeviceSize((extent.width + 1) / 2) * ((extent.height + 1) / 2) * 4;
}

// Each drawn point's shape operator in its tangent frame (shape.comp, shared/render.h's SILHOUETTE_BAND), once
// after the refinement: `shape` gets a vec4 a point of the draw, in its order. A global fit's are 0 (unknown: the
// style's τ), as its surface is evaluated in double only.
void computeShapes(Context& ctx, const GpuRefinement& r, uint32_t first, uint32_t points, const Buffer& shape) {
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    if (!r.partitionOfUnity() || points == 0) {
        submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            vkCmdFillBuffer(cmd, shape.buffer, 0, VK_WHOLE_SIZE, 0);
            stageBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute,
                         VK_ACCESS_2_SHADER_READ_BIT);
        });
        return;
    }
    std::vector<DescriptorBinding> bindings = puSurfaceBindings(r);
    bindings.push_back({gpu::SHAPE_POINTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, r.drawnPoints().buffer});
    bindings.push_back({gpu::SHAPE_OUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shape.buffer});
    DescriptorSet set = createDescriptorSet(ctx, bindings, VK_SHADER_STAGE_COMPUTE_BIT);
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    try {
        layout = createPipelineLayout(ctx, set.layout, sizeof(gpu::uvec4), VK_SHADER_STAGE_COMPUTE_BIT);
        pipeline = createComputePipeline(ctx, layout,
                                         r.nodesByAddress ? std::span<const uint32_t>(spv_shape_large_comp)
                                                          : std::span<const uint32_t>(spv_shape_comp));
        // A dispatch at most the device's workgroups (lavapipe's 65,535 hold 4.2M points), as many as it takes.
        const uint64_t most = uint64_t(ctx.properties.limits.maxComputeWorkGroupCount[0]) * gpu::SHAPE_GROUP_SIZE;
        submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set.set, 0, nullptr);
            for (uint64_t start = 0; start < points; start += most) {
                const uint32_t count = uint32_t(std::min<uint64_t>(most, points - start));
                const gpu::uvec4 range(first, points, uint32_t(start), 0);
                vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(range), &range);
                vkCmdDispatch(cmd, (count + gpu::SHAPE_GROUP_SIZE - 1) / gpu::SHAPE_GROUP_SIZE, 1, 1);
            }
            stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, compute, VK_ACCESS_2_SHADER_READ_BIT);
        });
    } catch (...) {
        vkDestroyPipeline(ctx.device, pipeline, nullptr);
        vkDestroyPipelineLayout(ctx.device, layout, nullptr);
        destroyDescriptorSet(ctx, set);
        throw;
    }
    vkDestroyPipeline(ctx.device, pipeline, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    destroyDescriptorSet(ctx, set);
}

// gpu::DrawnCounts at the start of a frame: no dots, empty bounds.
const gpu::DrawnCounts kNothingDrawn{gpu::uvec4(0), gpu::uvec4(UINT32_MAX, UINT32_MAX, 0, 0)};

}  // namespace

PointRenderer::PointRenderer(Context& ctx, std::vector<const GpuRefinement*> sets, VkFormat colorFormat,
                             uint32_t framesInFlight, const StrokeBuffers* strokes)
    : ctx_(ctx), frames_(std::max(1u, framesInFlight)) {
    // A throw half way (out of memory, a lost device) releases what was made: no destructor runs then.
    try {
        styleBuffer_ =
            createBuffer(ctx, sizeof(StyleBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         MemoryUse::Device);
        bool twoSided = false;
        for (const GpuRefinement* r : sets) {
            uint32_t draw[4];
            downloadBuffer(ctx, r->indirect, r->drawOffset(), draw, sizeof(draw));
            VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
            viewInfo.buffer = r->drawnPoints().buffer;
            viewInfo.format = VK_FORMAT_R32G32B32A32_SFLOAT;
            viewInfo.range = VK_WHOLE_SIZE;
            const bool direction = r->options.style == SampleStyle::Direction;
            sets_.push_back({VK_NULL_HANDLE, splatSpacing(*r), draw[0], draw[2], direction ? "direction" : "stipple",
                             r->selection ? float(r->selection->plan.areaEstimate) : 0.0f, direction, r->twoSided,
                             r->selection != nullptr && !direction});
            twoSided = twoSided || r->twoSided;
            VK_CHECK(vkCreateBufferView(ctx.device, &viewInfo, nullptr, &sets_.back().texels));
            Set& set = sets_.back();
            set.shape = createBuffer(ctx, VkDeviceSize(std::max(1u, set.points)) * sizeof(gpu::vec4),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                         VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                     MemoryUse::Device);
            viewInfo.buffer = set.shape.buffer;
            VK_CHECK(vkCreateBufferView(ctx.device, &viewInfo, nullptr, &set.shapeTexels));
            computeShapes(ctx, *r, set.first, set.points, set.shape);
        }
        const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        query.queryType = VK_QUERY_TYPE_TIMESTAMP;
        query.queryCount = kTimestamps;
        for (Frame& f : frames_) {
            f.drawn =
                createBuffer(ctx, sizeof(kNothingDrawn), storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Device);
            f.depth = createBuffer(ctx, 4, storage, MemoryUse::Device);
            f.coverage = createBuffer(ctx, 4, storage, MemoryUse::Device);
            f.spaceGrid = createBuffer(ctx, 16, storage, MemoryUse::Device);
            // The spacing's two lists of open dots (spacing.comp's SpaceOpen): a header and a word a point each.
            uint32_t most = 1;
            for (const Set& set : sets_) most = std::max(most, set.points);
            f.spaceOpen = createBuffer(ctx, 2 * (16 + 4 * VkDeviceSize(most)),
                                       storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, MemoryUse::Device);
            for (const Set& set : sets_)
                // `DotList`: the indirect dispatch, then up to one `Dot` a point.
                f.dots.push_back(
                    createBuffer(ctx, gpu::DOT_LIST_HEADER + sizeof(gpu::Dot) * VkDeviceSize(std::max(1u, set.points)),
                                 storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                 MemoryUse::Device));
            VK_CHECK(vkCreateQueryPool(ctx.device, &query, nullptr, &f.timestamps));
            bindDescriptors(f);
        }
        layout_ = createPipelineLayout(ctx, frames_.front().descriptors.front().layout, sizeof(Push), kStages);
        splat_ = createComputePipeline(ctx, layout_, spv_splat_comp);
        stamp_ = createComputePipeline(ctx, layout_, spv_stamp_comp);
        space_ = createComputePipeline(ctx, layout_, spv_spacing_comp);
        ink_ = createBlendedPipeline(ctx, layout_, colorFormat, spv_ink_vert, spv_ink_frag);
        if (strokes)
            lines_ = std::make_unique<LineRenderer>(ctx, *strokes, colorFormat, uint32_t(frames_.size()), twoSided);
    } catch (...) {
        release();
        throw;
    }
}

PointRenderer::~PointRenderer() { release(); }

void PointRenderer::release() {
    lines_.reset();
    for (VkPipeline p : {splat_, stamp_, space_, ink_}) vkDestroyPipeline(ctx_.device, p, nullptr);
    vkDestroyPipelineLayout(ctx_.device, layout_, nullptr);
    for (Frame& f : frames_) {
        vkDestroyQueryPool(ctx_.device, f.timestamps, nullptr);
        for (DescriptorSet& d : f.descriptors) destroyDescriptorSet(ctx_, d);
        for (Buffer& b : f.dots) destroyBuffer(ctx_, b);
        for (Buffer* b : {&f.coverage, &f.depth, &f.drawn, &f.spaceGrid, &f.spaceOpen}) destroyBuffer(ctx_, *b);
    }
    for (Set& s : sets_) {
        vkDestroyBufferView(ctx_.device, s.texels, nullptr);
        vkDestroyBufferView(ctx_.device, s.shapeTexels, nullptr);
        if (s.shape.buffer) destroyBuffer(ctx_, s.shape);
    }
    destroyBuffer(ctx_, styleBuffer_);
    frames_.clear();
    sets_.clear();
    splat_ = stamp_ = space_ = ink_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
}

void PointRenderer::bindDescriptors(Frame& f) {
    for (DescriptorSet& d : f.descriptors) destroyDescriptorSet(ctx_, d);
    f.descriptors.clear();
    for (size_t k = 0; k < sets_.size(); ++k)
        f.descriptors.push_back(
            createDescriptorSet(ctx_,
                                {{gpu::RENDER_DOTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.dots[k].buffer},
                                 {gpu::RENDER_STYLE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, styleBuffer_.buffer},
                                 {gpu::RENDER_DRAWN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.drawn.buffer},
                                 {gpu::RENDER_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.depth.buffer},
                                 {gpu::RENDER_POINT_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_NULL_HANDLE, 1,
                                  0, 0, sets_[k].texels},
                                 {gpu::RENDER_SHAPE_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_NULL_HANDLE, 1,
                                  0, 0, sets_[k].shapeTexels},
                                 {gpu::RENDER_COVERAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.coverage.buffer},
                                 {gpu::RENDER_SPACE_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.spaceGrid.buffer},
                                 {gpu::RENDER_SPACE_OPEN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, f.spaceOpen.buffer}},
                                kStages));
}

void PointRenderer::setStyle(VkCommandBuffer cmd, const RenderStyle& s, float pixelScale) {
    style_ = s;
    pixelScale_ = pixelScale;
    StyleBlock b{};
    b.color[0] = s.ink;
    b.color[1] = s.hiddenInk;
    b.size = glm::vec4(s.silhouetteSize * pixelScale, s.frontSize * pixelScale, s.hiddenSize * pixelScale, s.tau);
    b.light = glm::vec4(shaderLight(s), s.toneGamma);
    styleSpacing_ = spacingRadius(s, pixelScale);
    spacing_ = styleSpacing_;  // prepare() fits it to the target
    b.options = glm::vec4(s.lightFollowsCamera ? 0.0f : 1.0f, s.drawDots ? 0.0f : 1.0f, spacing_.x, spacing_.y);
    b.tone = glm::vec4(s.inkDensity, s.ambient, 1.0f, kMaxDotPixels * pixelScale);
    block_ = b;
    recordUniformUpdate(cmd, styleBuffer_, &b, sizeof(b));  // a frame still in flight may be reading the block
    if (lines_) lines_->setStyle(cmd, s, pixelScale);
}

PointRenderer::Push PointRenderer::push(const Set& s, const Camera& camera, VkExtent2D extent) const {
    glm::mat4 p = camera.projection(float(extent.width) / float(extent.height));
    // Tone: expected dots per pixel where the model faces the camera — the set's points over its surface area
    // when known, else half of them over the projected bounding sphere (radius ½ in normalized units).
    float pixelsPerUnit = std::abs(p[1][1]) * 0.5f * float(extent.height) / camera.distance;
    float points = float(std::max(1u, s.points));
    float sphereLambda = 0.5f * points / (float(M_PI) * 0.25f * pixelsPerUnit * pixelsPerUnit);
    float lambda = s.area > 0 ? points / (s.area * pixelsPerUnit * pixelsPerUnit) : sphereLambda;
    float dotPixels = float(M_PI) * 0.25f * std::pow(style_.frontSize * pixelScale_, 2.0f);
    // k: with screen spacing, kSupply times the candidates the tone asks for (splat.comp corrects for n·v and
    // depth); without, λ·(dot area)·k ≈ 0.9, so a fully dark region is about 60% ink at any zoom and point count.
    const bool spaced = spacing_.x > 0 && s.spaced;
    float k = spaced ? kSupply * kCoverage / (dotPixels * lambda) : std::min(1.0f, 0.9f / (sphereLambda * dotPixels));
    const float radius = style_.splatScale * s.splatRadius, pushBack = style_.occlusion ? radius : 0.0f;
    return Push{
        camera.view(), glm::vec4(p[0][0], p[1][1], p[2][2], p[3][2]),
        glm::vec4(extent.width, extent.height, (extent.width + 1) / 2, (extent.height + 1) / 2),
        glm::vec4(radius, pushBack, k, camera.distance * camera.distance),
        glm::uvec4(s.points,
                   (style_.hiddenLines ? gpu::CAMERA_HIDDEN : 0u) | (s.sparseSplats ? gpu::CAMERA_SPARSE_SPLATS : 0u) |
                       (spaced ? gpu::CAMERA_SPACED : 0u) | (s.twoSided ? gpu::CAMERA_TWO_SIDED : 0u),
                   s.first, gpu::PASS_VISIBILITY)};
}

void PointRenderer::prepare(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame) {
    Frame& f = frames_.at(frame);
    if (extent.width != f.extent.width || extent.height != f.extent.height) {
        if (depthGridBytes(extent) > ctx_.properties.limits.maxStorageBufferRange)
            throw Error("a " + std::to_string(extent.width) + "x" + std::to_string(extent.height) +
                        " target is too large for this device's storage buffers");
        vkDeviceWaitIdle(ctx_.device);
        destroyBuffer(ctx_, f.depth);
        destroyBuffer(ctx_, f.coverage);
        const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        // The depth grid has one cell per 2×2 pixels; coverage has 4 bits a pixel.
        f.depth = createBuffer(ctx_, depthGridBytes(extent), usage, MemoryUse::Device);
        f.coverage =
            createBuffer(ctx_, (VkDeviceSize(extent.width) * extent.height + 7) / 8 * 4, usage, MemoryUse::Device);
        f.extent = extent;
        bindDescriptors(f);
    }
    const glm::vec2 fitted =
        fitSpacing(styleSpacing_, (style_.ambient + 1.0f) * style_.inkDensity, extent, spacingGridLimit(ctx_));
    if (fitted != spacing_) {
        spacing_ = fitted;
        block_.options.z = spacing_.x;
        block_.options.w = spacing_.y;
        recordUniformUpdate(cmd, styleBuffer_, &block_, sizeof(block_));
    }
    const uint32_t cells = spacingCells(extent, spacing_.y);
    if (cells > f.spaceCells) {
        vkDeviceWaitIdle(ctx_.device);
        destroyBuffer(ctx_, f.spaceGrid);
        f.spaceGrid = createBuffer(
            ctx_, VkDeviceSize(cells) * 16,
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
            MemoryUse::Device);
        f.spaceCells = cells;
        bindDescriptors(f);
    }
    if (lines_) lines_->sync(frame, f.depth, f.coverage, f.drawn);
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const auto rw = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    const auto indirect = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
    const auto graphics = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    // This frame's previous passes (this frame slot's last use) may still use the buffers it clears.
    stageBarrier(cmd, graphics | compute | indirect, rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
                 VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, f.depth.buffer, 0, VK_WHOLE_SIZE, kFarDepth);
    vkCmdFillBuffer(cmd, f.coverage.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdUpdateBuffer(cmd, f.drawn.buffer, 0, sizeof(kNothingDrawn), &kNothingDrawn);
    const uint32_t noDots[4] = {0, 1, 1, 0};  // an empty list: no workgroups
    for (const Buffer& dots : f.dots) vkCmdUpdateBuffer(cmd, dots.buffer, 0, sizeof(noDots), noDots);
    if (lines_) lines_->recordReset(cmd, frame);
    stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute, rw);
    vkCmdResetQueryPool(cmd, f.timestamps, 0, kTimestamps);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, f.timestamps, 0);

    auto bind = [&](size_t k, uint32_t pass) {
        Push constants = push(sets_[k], camera, extent);
        constants.counts.w = pass;
        vkCmdPushConstants(cmd, layout_, kStages, 0, sizeof(constants), &constants);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &f.descriptors[k].set, 0, nullptr);
    };
    auto passBarrier = [&] {
        stageBarrier(cmd, compute, rw, compute | indirect, rw | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    };
    // Every set splats before any is tested: sets occlude each other.
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, splat_);
    for (size_t k = 0; k < sets_.size(); ++k) {
        bind(k, gpu::PASS_VISIBILITY);
        vkCmdDispatch(cmd, (sets_[k].points + kComputeGroup - 1) / kComputeGroup, 1, 1);
    }
    vkCmdWriteTimestamp2(cmd, compute, f.timestamps, 1);
    passBarrier();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, stamp_);
    for (size_t k = 0; k < sets_.size(); ++k) {
        bind(k, gpu::PASS_VISIBILITY);
        vkCmdDispatchIndirect(cmd, f.dots[k].buffer, 0);
    }
    passBarrier();
    // The silhouettes' strokes (stamp.comp): every set's visible silhouette dots into the coverage, then each
    // stroke reaching along the outline to the nearest of them.
    for (uint32_t pass : {gpu::PASS_OUTLINE, gpu::PASS_REACH}) {
        for (size_t k = 0; k < sets_.size(); ++k) {
            bind(k, pass);
            vkCmdDispatchIndirect(cmd, f.dots[k].buffer, 0);
        }
        passBarrier();
    }
    if (spacing_.x > 0) {
        // The screen spacing, a set at a time (spacing.comp): the grid cleared, then its rounds, each clearing the
        // cells' elections and emptying its list of open dots, then the relaxation of the accepted dots. The first
        // round's PASS_CLAIM_KEY visits every dot; the other passes visit the open dots it and each later one list.
        const VkDeviceSize plane = VkDeviceSize(cells) * 4;
        const VkDeviceSize openList = f.spaceOpen.size / 2;
        auto clear = [&](VkDeviceSize bytes, uint32_t round) {
            stageBarrier(cmd, compute, rw, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
            vkCmdFillBuffer(cmd, f.spaceGrid.buffer, 0, bytes, 0xFFFFFFFFu);
            const uint32_t empty[4] = {0, 1, 1, 0};
            vkCmdUpdateBuffer(cmd, f.spaceOpen.buffer, (round & 1) * openList, sizeof(empty), empty);
            stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute, rw);
        };
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, space_);
        for (size_t k = 0; k < sets_.size(); ++k) {
            if (!sets_[k].spaced) continue;
            for (uint32_t round = 0; round < gpu::SPACE_ROUNDS; ++round) {
                clear((round == 0 ? 4 : 2) * plane, round);
                for (uint32_t pass :
                     {gpu::PASS_CLAIM_KEY, gpu::PASS_CLAIM_POINT, gpu::PASS_CLAIM_DOT, gpu::PASS_DECIDE}) {
                    bind(k, pass | round << 8);
                    if (pass == gpu::PASS_CLAIM_KEY && round == 0)
                        vkCmdDispatchIndirect(cmd, f.dots[k].buffer, 0);
                    else
                        vkCmdDispatchIndirect(cmd, f.spaceOpen.buffer,
                                              ((pass == gpu::PASS_CLAIM_KEY ? round - 1 : round) & 1) * openList);
                    passBarrier();
                }
            }
            // The relaxation: no displacement yet, an empty list of the accepted dots and empty blocks, the list,
            // its steps over the list, then the dots moved.
            if (!style_.relaxDots || cells < gpu::SPACE_RELAX_MIN_CELLS) continue;
            stageBarrier(cmd, compute, rw, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
            const uint32_t header[4] = {0, 1, 1, 0};
            vkCmdFillBuffer(cmd, f.spaceGrid.buffer, 0, 2 * plane, 0);
            vkCmdUpdateBuffer(cmd, f.spaceGrid.buffer, 2 * plane, sizeof(header), header);
            vkCmdFillBuffer(cmd, f.spaceGrid.buffer, 2 * plane + sizeof(header), plane - sizeof(header), 0);
            stageBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, compute, rw);
            bind(k, gpu::PASS_LIST);
            vkCmdDispatchIndirect(cmd, f.dots[k].buffer, 0);
            passBarrier();
            for (uint32_t step = 0; step <= gpu::SPACE_RELAX_ROUNDS; ++step) {
                bind(k, step < gpu::SPACE_RELAX_ROUNDS ? gpu::PASS_RELAX | step << 8 : gpu::PASS_PLACE);
                vkCmdDispatchIndirect(cmd, f.spaceGrid.buffer, 2 * plane);
                passBarrier();
            }
        }
    }
    vkCmdWriteTimestamp2(cmd, compute, f.timestamps, 2);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, stamp_);
    for (size_t k = 0; k < sets_.size(); ++k) {
        bind(k, gpu::PASS_STAMP);
        vkCmdDispatchIndirect(cmd, f.dots[k].buffer, 0);
    }
    if (lines_) {
        // The pen lines against the same depth, pushed back as the dots are.
        float pushBack = 0;
        if (style_.occlusion)
            for (const Set& s : sets_) pushBack = std::max(pushBack, style_.splatScale * s.splatRadius);
        glm::mat4 p = camera.projection(float(extent.width) / float(extent.height));
        lines_->recordCull(cmd, camera.view(), glm::vec4(p[0][0], p[1][1], p[2][2], p[3][2]), extent, pushBack, frame);
        if (lines_->stamps()) {
            stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, compute, rw);
            lines_->recordStamp(cmd, frame);
        }
    }
    vkCmdWriteTimestamp2(cmd, compute, f.timestamps, 3);
    stageBarrier(cmd, compute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, graphics | indirect,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

void PointRenderer::draw(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame) const {
    VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, ink_);
    // Every set stamped into the same coverage: one triangle inks them all.
    Push constants = push(sets_.front(), camera, extent);
    vkCmdPushConstants(cmd, layout_, kStages, 0, sizeof(constants), &constants);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1,
                            &frames_.at(frame).descriptors.front().set, 0, nullptr);
    vkCmdDraw(cmd, 6, 1, 0, 0);
    if (lines_) lines_->recordDraw(cmd, extent, frame);
}

void PointRenderer::recordFrame(VkCommandBuffer cmd, const Camera& camera, const FrameTarget& target, uint32_t frame,
                                const Buffer* readback) {
    const VkExtent2D extent = target.extent;
    prepare(cmd, camera, extent, frame);
    const auto colorStage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    imageBarrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, target.previousStages, 0, colorStage,
                 VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);

    const glm::vec4& paper = style_.paper;
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = target.view;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{paper.r, paper.g, paper.b, paper.a}};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &rendering);
    draw(cmd, camera, extent, frame);
    vkCmdEndRendering(cmd);
    writeEnd(cmd, frame);

    VkImageLayout layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkPipelineStageFlags2 stage = colorStage;
    VkAccessFlags2 access = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    if (readback) {
        imageBarrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                     colorStage, access, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, target.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback->buffer, 1, &region);
        stageBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        stage = VK_PIPELINE_STAGE_2_COPY_BIT;
        access = 0;  // a read: only the layout change must wait for it
    }
    // Presentation waits on the submission's semaphore; anything else the caller records after the frame in the
    // same command buffer (a copy, sampling) must follow the layout change.
    const bool present = target.finalLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    if (target.finalLayout != layout || !present)
        imageBarrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, layout, target.finalLayout, stage, access,
                     present ? VK_PIPELINE_STAGE_2_NONE : VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     present ? 0 : VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
}

void PointRenderer::writeEnd(VkCommandBuffer cmd, uint32_t frame) const {
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, frames_.at(frame).timestamps, kTimestamps - 1);
}

PointRenderer::Timings PointRenderer::timings(uint32_t frame) const {
    uint64_t t[kTimestamps] = {};
    if (vkGetQueryPoolResults(ctx_.device, frames_.at(frame).timestamps, 0, kTimestamps, sizeof(t), t, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
        return {};
    double ms = ctx_.properties.limits.timestampPeriod * 1e-6;
    return {double(t[1] - t[0]) * ms, double(t[3] - t[2]) * ms, double(t[4] - t[3]) * ms, double(t[2] - t[1]) * ms};
}

void checkOffscreenSize(const Context& ctx, uint32_t width, uint32_t height, uint32_t supersample) {
    const std::string what = "image size " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                             std::to_string(supersample) + "x supersampling";
    uint32_t maxSide = std::min(ctx.properties.limits.maxImageDimension2D, 16384u);
    // In 64 bits: a huge supersampling wrapped around 2³² to a small (or 0×0) image.
    if (width == 0 || height == 0 || supersample == 0 || uint64_t(width) * supersample > maxSide ||
        uint64_t(height) * supersample > maxSide)
        throw Error(what + " is outside 1.." + std::to_string(maxSide / std::max(1u, supersample)) + " pixels a side");
    VkDeviceSize bytes = depthGridBytes({width * supersample, height * supersample});
    VkDeviceSize limit = ctx.properties.limits.maxStorageBufferRange;
    if (bytes > limit)
        throw Error(what + " needs a " + std::to_string(bytes >> 20) + " MiB depth grid, more than this device's " +
                    std::to_string(limit >> 20) + " MiB storage buffers: use a smaller size or less supersampling");
}

uint32_t PointRenderer::drawnDots(uint32_t frame) const {
    vkDeviceWaitIdle(ctx_.device);
    uint32_t dots = 0;
    downloadBuffer(ctx_, frames_.at(frame).drawn, 0, &dots, sizeof(dots));
    return dots;
}

std::vector<DrawnSegment> PointRenderer::drawnSegments(StrokeBuffers::Kind kind, uint32_t frame) const {
    return lines_ ? lines_->drawn(kind, frame) : std::vector<DrawnSegment>{};
}

std::vector<gpu::Dot> PointRenderer::dotList(size_t set, uint32_t frame) const {
    vkDeviceWaitIdle(ctx_.device);
    const Buffer& list = frames_.at(frame).dots.at(set);
    uint32_t header[4];
    downloadBuffer(ctx_, list, 0, header, sizeof(header));
    std::vector<gpu::Dot> dots(header[3]);
    if (!dots.empty()) downloadBuffer(ctx_, list, gpu::DOT_LIST_HEADER, dots.data(), dots.size() * sizeof(gpu::Dot));
    return dots;
}

std::vector<gpu::vec4> PointRenderer::shapes(size_t set) const {
    vkDeviceWaitIdle(ctx_.device);
    const Set& s = sets_.at(set);
    std::vector<gpu::vec4> out(s.points);
    if (!out.empty()) downloadBuffer(ctx_, s.shape, 0, out.data(), out.size() * sizeof(gpu::vec4));
    return out;
}

std::vector<uint32_t> PointRenderer::drawnPoints(size_t set, uint32_t frame) const {
    std::vector<gpu::Dot> dots = dotList(set, frame);
    std::vector<uint32_t> points;
    for (const gpu::Dot& d : dots)
        if (((d.cls >> 2) & 3u) != gpu::BACK) points.push_back(d.cls >> 4);
    std::sort(points.begin(), points.end());
    return points;
}

VectorDrawing PointRenderer::vectorDrawing(uint32_t frame) const {
    vkDeviceWaitIdle(ctx_.device);
    const Frame& f = frames_.at(frame);
    VectorDrawing out;
    out.width = f.extent.width;
    out.height = f.extent.height;
    out.paper = style_.paper;
    // The classes (gpu::SILHOUETTE, FRONT, BACK, HIDDEN) and stamp.comp's sizes: a dot's diameter is its class's
    // size times its scale, clamped to [tone.z, tone.w] (setStyle).
    const float sizes[4] = {style_.silhouetteSize, style_.frontSize, 0.0f, style_.hiddenSize};
    const float maxDiameter = kMaxDotPixels * pixelScale_;
    for (size_t k = 0; k < sets_.size(); ++k) {
        uint32_t header[4];
        downloadBuffer(ctx_, f.dots[k], 0, header, sizeof(header));
        std::vector<gpu::Dot> dots(header[3]);
        if (!dots.empty())
            downloadBuffer(ctx_, f.dots[k], gpu::DOT_LIST_HEADER, dots.data(), dots.size() * sizeof(gpu::Dot));
        struct Mark {
            uint32_t point, cls;
            glm::vec2 pixel;
            float scale;
            glm::vec2 along;
        };
        std::vector<Mark> marks;
        for (const gpu::Dot& d : dots) {
            uint32_t cls = (d.cls >> 2) & 3u;
            if (cls != gpu::BACK) marks.push_back({d.cls >> 4, cls, d.pixel, d.scale, d.along});
        }
        std::sort(marks.begin(), marks.end(), [](const Mark& a, const Mark& b) { return a.point < b.point; });
        VectorLayer& shown = out.layer(sets_[k].name, style_.ink);
        std::vector<VectorLayer::Dot> hidden;
        for (const Mark& m : marks) {
            VectorLayer::Dot dot{m.pixel, std::clamp(sizes[m.cls] * pixelScale_ * m.scale, 1.0f, maxDiameter), m.along};
            (m.cls == gpu::HIDDEN ? hidden : shown.dots).push_back(dot);
        }
        if (!hidden.empty()) {
            VectorLayer& layer = out.layer("hidden", style_.hiddenInk, true);
            layer.dots.insert(layer.dots.end(), hidden.begin(), hidden.end());
        }
    }
    if (lines_) {
        // The pen lines as the frame decided them: runs of consecutive drawn segments of a stroke are polylines,
        // hatching in a layer of its own, contours above it and their hidden parts below everything.
        auto chains = [&](StrokeBuffers::Kind kind) {
            std::vector<DrawnSegment> drawn = lines_->drawn(kind, frame);
            std::vector<Stroke> strokes;
            for (size_t i = 0; i < drawn.size(); ++i) {
                const DrawnSegment& d = drawn[i];
                bool joins = i > 0 && d.segment == drawn[i - 1].segment + 1 &&
                             glm::length(d.a - drawn[i - 1].b) < 1e-3f * float(out.width);
                if (!joins) strokes.push_back({{d.a}, {}});
                strokes.back().points.push_back(d.b);
                strokes.back().visible.push_back((d.flags & kSegmentVisible) != 0);
            }
            return strokes;
        };
        out.addStrokes("hatching", style_.ink, chains(StrokeBuffers::Hatching));
        out.addStrokes("contour", style_.ink, chains(StrokeBuffers::Contours),
                       style_.hiddenLines ? "hidden contour" : "", style_.hiddenInk);
        // Crease and boundary lines on pens of their own (docs/lines.md); their hidden parts join the hidden contours.
        out.addStrokes("creases", style_.ink, chains(StrokeBuffers::Creases),
                       style_.hiddenLines ? "hidden contour" : "", style_.hiddenInk);
        out.addStrokes("boundaries", style_.ink, chains(StrokeBuffers::Boundaries),
                       style_.hiddenLines ? "hidden contour" : "", style_.hiddenInk);
        // Layers with nothing in them are left out.
        std::erase_if(out.layers, [](const VectorLayer& l) { return l.dots.empty() && l.lines.empty(); });
    }
    return out;
}

OffscreenRenderer::OffscreenRenderer(Context& ctx, uint32_t width, uint32_t height, const RenderStyle& style,
                                     std::vector<const GpuRefinement*> sets, const StrokeBuffers* strokes)
    : ctx_(ctx), factor_(std::max(1u, style.supersample)), renderer_(ctx, std::move(sets), kColorFormat, 1, strokes) {
    checkOffscreenSize(ctx, width, height, factor_);
    uint32_t w = width * factor_, h = height * factor_;
    try {
        color_ =
            createImage(ctx, w, h, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                        VK_IMAGE_ASPECT_COLOR_BIT);
        readback_ = createBuffer(ctx, VkDeviceSize(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback);
        setStyle(style);
    } catch (...) {
        destroyImage(ctx, color_);
        destroyBuffer(ctx, readback_);
        throw;
    }
}

OffscreenRenderer::~OffscreenRenderer() {
    destroyImage(ctx_, color_);
    destroyBuffer(ctx_, readback_);
}

void OffscreenRenderer::setStyle(const RenderStyle& style) {
    submitAndWait(ctx_, [&](VkCommandBuffer cmd) { renderer_.setStyle(cmd, style, float(factor_)); });
}

FrameTarget OffscreenRenderer::target() const {
    // The image's last use was a copy (render) or the ink itself (draw), in a submission waited for.
    return {color_.image, color_.view, color_.extent, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT};
}

RgbaImage OffscreenRenderer::render(const Camera& camera) {
    submitAndWait(ctx_, [&](VkCommandBuffer cmd) { renderer_.recordFrame(cmd, camera, target(), 0, &readback_); });
    VkExtent2D extent = color_.extent;
    RgbaImage full{extent.width, extent.height, {}};
    full.pixels.resize(size_t(extent.width) * extent.height * 4);
    std::memcpy(full.pixels.data(), readback_.mapped, full.pixels.size());
    return downsample(full, factor_);
}

VectorDrawing OffscreenRenderer::vectorDrawing() const {
    VectorDrawing d = renderer_.vectorDrawing();
    const float scale = 1.0f / float(factor_);
    d.width /= factor_;
    d.height /= factor_;
    for (VectorLayer& layer : d.layers) {
        for (VectorLayer::Dot& dot : layer.dots) dot.center *= scale, dot.diameter *= scale, dot.along *= scale;
        for (std::vector<glm::vec2>& line : layer.lines)
            for (glm::vec2& p : line) p *= scale;
    }
    return d;
}

void OffscreenRenderer::draw(const Camera& camera) {
    submitAndWait(ctx_, [&](VkCommandBuffer cmd) { renderer_.recordFrame(cmd, camera, target()); });
}

}  // namespace ink
