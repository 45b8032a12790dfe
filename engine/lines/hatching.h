// Hatching strokes on the HRBF surface (docs/lines.md): long, evenly spaced streamlines of a cross field that
// follows the form (cross_field.h), traced once per model on the CPU in object space. The device decides each frame
// which strokes show, by tone and visibility (lines.comp). No Vulkan here.
#pragma once

#include "inkwell/ranges.h"
#include "lines/cross_field.h"
#include "lines/lines.h"

#include <vector>

namespace ink {

// Along the field, across it, diagonal to both (the ranges' table, include/inkwell/ranges.h).
constexpr uint32_t kMaxHatchFamilies = uint32_t(inkwell::ranges::hatchFamilies.hi);
// The kind bits hold a family in 2 bits (HATCH_FAMILY_SHIFT), and lines.comp draws every family past the second
// as the diagonal: three at most.
static_assert(kMaxHatchFamilies <= 3, "a fourth hatching family needs its own kind bits and shading");

struct HatchOptions {
    double spacing = 0.007;  // separation of the finest level, normalized units: about 6 pixels at the default view
    double testRatio = 0.6;  // a stroke stops closer than this × its separation to another (d_test / d_sep)
    uint32_t families = 3;   // 1: no crossing strokes; 2: no diagonal ones in the darkest tones
    uint32_t levels = 2;     // level k is traced at spacing · 2^(levels − 1 − k)
    double minLengthRatio = 3.0;  // strokes shorter than this × their separation are dropped
    // A stroke ends where the field's neighbours disagree (coherence below this: a singularity of the cross field)
    // or where it would turn by more than maxTurnDeg in one step (spacing / 2).
    double minCoherence = 0.5;
    double maxTurnDeg = 20;
    CrossFieldOptions field;
};

struct HatchStats {
    size_t strokes = 0, vertices = 0;
    double length = 0;             // normalized units
    double fieldSeconds = 0;       // the cross field: its graph, solve, comb and look-up grid
    double fieldGraphSeconds = 0;  // of which the graph (buildCrossFieldGraph)
    bool fieldOnDevice = false;    // solved on the device (cross_field_device.h), else on the CPU
    double fieldDeviceMs = 0;      // the device's passes (timestamps)
    double seconds = 0;            // all of it
};

// Streamlines of the cross field on f = 0, seeded à la Jobard & Lefer (1997): beside every accepted stroke at the
// separation d_sep, then from the samples for what those do not reach. Family 0 starts along the larger principal
// curvature (strokes wrap round the form), family 1 across it, family 2 at 45° to both; along a stroke the field's four
// directions are matched to the stroke's own. Each step (spacing / 2) is projected back onto the surface by Newton
// steps along ∇f. A stroke ends where it comes closer than d_test to another of its family (tested against a spatial
// hash), where the field has a singularity or turns sharply, or where it closes. Families are traced in parallel.
std::vector<PenStroke> traceHatching(const Surface& hrbf, const std::vector<SurfaceSample>& samples,
                                     const HatchOptions& options = {}, HatchStats* stats = nullptr);

// The same with a field already computed on the samples.
std::vector<PenStroke> traceHatching(const Surface& hrbf, const CrossField& field, const HatchOptions& options = {},
                                     HatchStats* stats = nullptr);

}  // namespace ink
