// Point sets on the HRBF surface (report §4, §6.2): seeds, then refinement levels of stippling or direction
// sampling, each child projected onto f = 0. The GPU path records every level into one command buffer with
// barriers between passes (no CPU round trip); the CPU reference (refine_cpu.cpp) follows the same rules
// and the same random numbers.
#pragma once

#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "refine/refine_plan.h"

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ink {

struct GpuSelection;  // select.h

// Device resources of one refinement, and of the stipple selection that follows it when the options select
// (RefineOptions::selects). drawnPoints() and drawOffset() are what the renderer reads.
struct GpuRefinement {
    RefinePlan plan;
    RefineOptions options;
    Buffer hrbfHeader, hrbf, points, candidates, flags, blocks, levels, indirect, seeds;
    Buffer puPatches, puNodes, puCells, puCoarse;  // the partition of unity (hrbfHeader is its header then)
    DescriptorSet descriptors;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline refine = VK_NULL_HANDLE, scan = VK_NULL_HANDLE, compact = VK_NULL_HANDLE;
    bool nodesByAddress = false;  // the partition of unity's nodes read by device address (refine_large.comp)
    VkQueryPool timestamps = VK_NULL_HANDLE;
    GpuSelection* selection = nullptr;  // owned; null when every refined point is drawn
    HostMs hostMs;                      // of making and running it (select.h)
    // The points lie on a surface that may be open (the scene sets it from Model::twoSided): its back, where it
    // shows through an opening, is drawn too (gpu::CAMERA_TWO_SIDED).
    bool twoSided = false;
    // In `indirect` (gpu::IndirectArgs): the refinement's VkDrawIndirectCommand, and the selection's.
    static constexpr VkDeviceSize kDrawOffset = offsetof(gpu::IndirectArgs, draw);
    static constexpr VkDeviceSize kSelectedDrawOffset = offsetof(gpu::IndirectArgs, selectedDraw);

    // The points drawn: the selected stipples (rank in `tone`), or the refined points.
    const Buffer& drawnPoints() const;
    // The surface is the partition of unity (evaluated in float, on the device by the passes that take
    // puSurfaceBindings), not the global fit (in double).
    bool partitionOfUnity() const { return puPatches.buffer != VK_NULL_HANDLE; }
    VkDeviceSize drawOffset() const { return selection ? kSelectedDrawOffset : kDrawOffset; }
};

void createRefinement(Context& ctx, GpuRefinement& r, const Surface& hrbf, const RefineOptions& options);
// The partition of unity's bindings (shared/refine.h: the header, REFINE_PU_*; the nodes unless read by address),
// for the passes that evaluate a refinement's surface in their own descriptor sets (the contour, the cross field).
std::vector<DescriptorBinding> puSurfaceBindings(const GpuRefinement& r);
void destroyRefinement(Context& ctx, GpuRefinement& r);

// Owns one GpuRefinement: created in the constructor (what was made is released when that throws), destroyed
// with the owner.
class Refinement {
public:
    Refinement(Context& ctx, const Surface& hrbf, const RefineOptions& options);
    ~Refinement() { destroyRefinement(ctx_, r_); }
    Refinement(const Refinement&) = delete;
    Refinement& operator=(const Refinement&) = delete;

    GpuRefinement& gpu() { return r_; }
    const GpuRefinement& gpu() const { return r_; }

private:
    Context& ctx_;
    GpuRefinement r_;
};
// Records every level: refine → scan → compact per level, synchronization2 barriers between them, then the
// selection; ends with a barrier that makes the points and draw arguments visible to compute shaders (as
// storage and as uniform texels), indirect commands and copies.
void recordRefinement(Context& ctx, VkCommandBuffer cmd, GpuRefinement& r);
// Records, submits and waits: the whole refinement in one submission.
void runRefinement(Context& ctx, GpuRefinement& r);
std::vector<LevelStats> readLevelStats(Context& ctx, GpuRefinement& r);
// Milliseconds the stipple selection took on the device (timestamps); 0 without one.
double selectionMs(Context& ctx, GpuRefinement& r);
// The refined points (all levels, or the last), in point-buffer order: the selection's candidates.
std::vector<PointRecord> readPoints(Context& ctx, GpuRefinement& r);
uint32_t readPointCount(Context& ctx, GpuRefinement& r);  // how many, without reading them
// The points the renderer draws: the selected stipples in candidate order, or the refined points.
std::vector<PointRecord> readDrawnPoints(Context& ctx, GpuRefinement& r);

}  // namespace ink
