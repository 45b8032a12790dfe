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

#include "pipelines.h"
#include "refine_plan.h"
#include "resources.h"

#include <cstdint>
#include <vector>

namespace ink {

constexpr uint32_t kMaxSelectStages = 48;  // MAX_STAGES in select_common.glsl

struct SelectOptions {
    float candidatesPerStipple = 4.0f;  // R₀ is chosen so that the selection keeps about one candidate in this many
    float growth = 1.18920712f;         // g = 2^(1/4): each stage about √2 times the points of the one before
    float poolFactor = 6.0f;            // a stage's pool: about this many candidates per point it will hold
    uint32_t seed = 1;
};

// One stage as the device sees it (`Stage` in select_common.glsl, std430). Computed on the CPU, identical
// for both backends.
struct SelectStage {
    float offset[3] = {0, 0, 0};   // a random shift of the grid per stage, so that cell borders do not align
    float cellScale = 0;           // 1 / cell side, the side a little above R_s
    float radius2 = 0;             // R_s²
    float previousRadius2 = 0;     // R_{s−1}² (0 for the first stage)
    float orderScale = 0;          // 1 / (R_{s−1}² − R_s²)
    uint32_t poolThreshold = 0;    // candidates whose pool key is below this are in the pool (see poolKey)
    uint32_t bucketsPerPhase = 0;  // a power of two
    uint32_t seed = 0;
    uint32_t pad[2] = {0, 0};
};
static_assert(sizeof(SelectStage) == 48);

struct SelectPlan {
    double radius0 = 0;       // R₀, normalized units
    double areaEstimate = 0;  // of the surface, normalized units (from the HRBF centres)
    uint32_t poolSeed = 0;
    std::vector<SelectStage> stages;  // coarse to fine
};

inline SelectOptions selectOptions(const RefineOptions& r) {
    SelectOptions o;
    o.candidatesPerStipple = r.candidatesPerStipple;
    o.seed = r.seed;
    return o;
}

// The plan for a refinement's candidates: `expectedCandidates` sizes the first hash tables and R₀.
SelectPlan planSelection(const Hrbf& hrbf, const RefinePlan& refine, const SelectOptions& options);

// The selected points in candidate order, with `tone` set to the rank and `level` kept; the points each stage
// added in `added` when non-null. The reference of select_*.comp: the same decisions, bit for bit.
std::vector<PointRecord> selectOnCpu(const std::vector<PointRecord>& candidates, const SelectPlan& plan,
                                     std::vector<uint32_t>* added = nullptr);

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
void createSelection(Context& ctx, GpuSelection& s, const Hrbf& hrbf, const RefinePlan& refine,
                     const SelectOptions& options, const Buffer& points, const Buffer& indirect);
void destroySelection(Context& ctx, GpuSelection& s);
// Records every stage, synchronization2 barriers between passes, after the refinement's last pass.
void recordSelection(VkCommandBuffer cmd, const GpuSelection& s);
// Points each stage added (reads back; the device must be idle).
std::vector<uint32_t> readStageCounts(Context& ctx, const GpuSelection& s);

// rank = (before + u·added) / total, below 1.
inline float stippleRank(uint32_t before, uint32_t added, uint32_t total, float u) {
    float r = (float(before) + u * float(added)) / float(total);
    return r < 1.0f ? r : 0.99999994f;
}

}  // namespace ink
