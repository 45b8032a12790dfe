// A point on the surface as the device stores it, and as the CPU reference, the exports and the spacing
// measures read it (no Vulkan here).
#pragma once

#include <cstdint>

namespace ink {

// Matches `Point` in common.glsl (std430, 32 bytes).
struct PointRecord {
    float position[3];  // normalized coordinates (Frame)
    uint32_t level;     // the refinement level that made it
    float normal[3];    // unit ∇f
    // A refined point: fixed per point in [0,1), coarser levels smaller (refine_bindings.glsl); a selected
    // stipple: its rank (select.h).
    float tone;
};
static_assert(sizeof(PointRecord) == 32);

}  // namespace ink
