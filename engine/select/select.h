// Stipple selection: from the refinement's candidate points, a subset with blue-noise spacing on the surface,
// each selected point carrying a progressive rank (docs/algorithm.md §3).
//
// Stages s = 0..K−1 run from coarse to fine with radii R_s = R₀·g^(K−1−s), the last one R₀. Each adds to the
// points selected so far a maximal set of new ones from its pool, no two points on the same side of the surface
// closer than R_s: the greedy set in a random priority order, computed in parallel with phase groups (Wei
// 2008): cells of side just above R_s, 8 phases by the parities of the cell's coordinates; cells of one phase
// are more than R_s apart, so one invocation per cell decides its candidates, highest priority first, against
// the points already selected. A stage's pool is a fixed random subset of the candidates, about `poolFactor`
// times the points it will hold (every candidate at the last stage); pools are nested, so every stage sees the
// points selected before it. The sets S_0 ⊂ S_1 ⊂ … ⊂ S_{K−1} each have blue-noise spacing at their radius, and
//   rank(p) = (|S_{s−1}| + u(p)·(|S_s| − |S_{s−1}|)) / |S_{K−1}|    for p added at stage s,
// u(p) ordering a stage's points by their distance to S_{s−1}, farthest first: the prefix {rank < t} is a
// coarser set plus the points of the next one that fill its largest holes.
#pragma once

#include "gpu/pipelines.h"
#include "gpu/resources.h"
#include "select/select_plan.h"

#include <cstdint>
#include <vector>

namespace ink {

// The device side: buffers and pipelines of one selection, run after the refinement in its command buffer.
// `stipples` holds the selected points in candidate order, their draw (count, 1, 0, 0) follows the
// refinement's in its `indirect` buffer.
struct GpuSelection {
    SelectPlan plan;
    Buffer stages, stageOf, order, pool, entryPoints, entryStage, bucketCount, bucketStart, backFill, blockSums, counts,
        stipples;
    DescriptorSet descriptors;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline setup = VK_NULL_HANDLE, poolSort = VK_NULL_HANDLE, bucket = VK_NULL_HANDLE, scan = VK_NULL_HANDLE,
               sort = VK_NULL_HANDLE, cover = VK_NULL_HANDLE, phase = VK_NULL_HANDLE, output = VK_NULL_HANDLE;
};

// `points` and `indirect` are the refinement's (GpuRefinement), read on the device; `maxCandidates` bounds
// its draw.
// Its upload joins `uploads` (the caller submits it); its host milliseconds are added to `host`.
void createSelection(Context& ctx, GpuSelection& s, const Surface& hrbf, const RefinePlan& refine,
                     const SelectOptions& options, const Buffer& points, const Buffer& indirect, UploadBatch& uploads,
                     HostMs& host);
void destroySelection(Context& ctx, GpuSelection& s);
// Records every stage, synchronization2 barriers between passes, after the refinement's last pass.
void recordSelection(VkCommandBuffer cmd, const GpuSelection& s);
// Points each stage added (reads back; the device must be idle).
std::vector<uint32_t> readStageCounts(Context& ctx, const GpuSelection& s);

}  // namespace ink
