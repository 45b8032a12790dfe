// A point on the surface as the device stores it, and as the CPU reference, the exports and the spacing
// measures read it (no Vulkan here).
#pragma once

#include "shared/refine.h"

#include <cstddef>
#include <cstdint>

namespace ink {

// The host view of gpu::Point (spirv_shaders/shared/refine.h) in plain floats: the same layout, checked below.
struct PointRecord {
    float position[3];  // normalized coordinates (Frame)
    uint32_t level;     // the refinement level that made it
    float normal[3];    // unit ∇f
    // A refined point: fixed per point in [0,1), coarser levels smaller (refine_bindings.glsl); a selected
    // stipple: its rank (select.h).
    float tone;
};
static_assert(sizeof(PointRecord) == sizeof(gpu::Point));
static_assert(offsetof(PointRecord, level) == offsetof(gpu::Point, level));
static_assert(offsetof(PointRecord, normal) == offsetof(gpu::Point, normal));
static_assert(offsetof(PointRecord, tone) == offsetof(gpu::Point, tone));

}  // namespace ink
