// The stipple selection's plan (stages, radii, pools) and its CPU reference: what both backends follow
// (select.h explains the method; the device side is there). No Vulkan here.
#pragma once

#include "refine/refine_plan.h"
#include "shared/select.h"  // the selection device side (spirv_shaders/shared/)

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ink {

constexpr uint32_t kMaxSelectStages = gpu::MAX_STAGES;

struct SelectOptions {
    float candidatesPerStipple = 4.0f;  // R₀ is chosen so that the selection keeps about one candidate in this many
    float growth = 1.18920712f;         // g = 2^(1/4): each stage about √2 times the points of the one before
    float poolFactor = 6.0f;            // a stage's pool: about this many candidates per point it will hold
    uint32_t seed = 1;
};

// One stage as the device sees it (gpu::Stage, std430). Computed on the CPU, identical
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
// The host view of gpu::Stage (spirv_shaders/shared/select.h) in plain floats: the same layout.
static_assert(sizeof(SelectStage) == sizeof(gpu::Stage));
static_assert(offsetof(SelectStage, cellScale) == offsetof(gpu::Stage, cellScale));
static_assert(offsetof(SelectStage, radius2) == offsetof(gpu::Stage, radius2));
static_assert(offsetof(SelectStage, previousRadius2) == offsetof(gpu::Stage, previousRadius2));
static_assert(offsetof(SelectStage, orderScale) == offsetof(gpu::Stage, orderScale));
static_assert(offsetof(SelectStage, poolThreshold) == offsetof(gpu::Stage, poolThreshold));
static_assert(offsetof(SelectStage, bucketsPerPhase) == offsetof(gpu::Stage, bucketsPerPhase));
static_assert(offsetof(SelectStage, seed) == offsetof(gpu::Stage, seed));
static_assert(offsetof(SelectStage, pad) == offsetof(gpu::Stage, pad));

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
SelectPlan planSelection(const Surface& hrbf, const RefinePlan& refine, const SelectOptions& options);

// The selected points in candidate order, with `tone` set to the rank and `level` kept; the points each stage
// added in `added` when non-null. The reference of select_*.comp: the same decisions, bit for bit.
std::vector<PointRecord> selectOnCpu(const std::vector<PointRecord>& candidates, const SelectPlan& plan,
                                     std::vector<uint32_t>* added = nullptr);

// rank = (before + u·added) / total, below 1.
inline float stippleRank(uint32_t before, uint32_t added, uint32_t total, float u) {
    float r = (float(before) + u * float(added)) / float(total);
    return r < 1.0f ? r : 0.99999994f;
}

}  // namespace ink
