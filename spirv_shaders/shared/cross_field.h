// The hatching's cross field solved on the device (cross_field.comp, cross_field_large.comp;
// engine/lines/cross_field_device.cpp): the push constants, the passes and the descriptor set's bindings (see
// interface.h). The set also holds the refinement's surface bindings (shared/refine.h: REFINE_SURFACE_HEADER,
// REFINE_PU_*), which pu_hrbf.glsl reads. The CPU twin is solveCrossField (engine/lines/cross_field.cpp): the same
// graph, the same passes, in double.
#ifndef INK_SHARED_CROSS_FIELD_H
#define INK_SHARED_CROSS_FIELD_H

#include "interface.h"

INK_BEGIN

INK_CONST uint FIELD_GROUP_SIZE = 64u;
INK_CONST uint FIELD_NONE = 0xFFFFFFFFu;  // no neighbour, no parent (CrossFieldGraph::kNone)

// Passes (FieldParams::range.z), each over the points [range.x, range.y) of one level, one invocation a point.
INK_CONST uint FIELD_PASS_SEED = 0u;      // the samples: normal, principal direction and confidence from ∇f and HF
INK_CONST uint FIELD_PASS_RESTRICT = 1u;  // a coarse level: each point's seed from its children's
INK_CONST uint FIELD_PASS_START = 2u;     // the coarsest level: the direction is the seed, or where the curvature
                                          // gives none (FIELD_START_CONFIDENCE) the tangent of a fixed axis
INK_CONST uint FIELD_PASS_SMOOTH = 3u;    // a Jacobi sweep: FIELD_DIRECTIONS half range.w read, the other written
INK_CONST uint FIELD_PASS_PROLONG = 4u;   // a finer level: its parent's direction in its tangent plane

// Below this confidence a coarsest point starts from the tangent plane's projection of the model's y axis (its
// x axis where the normal lies within 18° of ±y) instead of its seed: where the surface is flat or umbilic the
// seed's direction is the Hessian's rounding noise, different in float and double, and the sweeps would smooth
// that noise instead of growing the field in from the curved parts.
INK_CONST float FIELD_START_CONFIDENCE = 0.02;

// The push constants (std430).
struct FieldParams {
    uvec4 range;   // x, y: the level's points; z: the pass; w: the half of FIELD_DIRECTIONS a sweep reads (0, 1)
    uvec4 counts;  // x: all points, y: the neighbours a point (k), z: the samples; w unused
    vec4 options;  // x: fidelity, y: feature size; z, w unused
};
INK_ASSERT_SIZE(FieldParams, 48);
INK_ASSERT_OFFSET(FieldParams, counts, 16);
INK_ASSERT_OFFSET(FieldParams, options, 32);

// The descriptor set's own bindings (after the refinement's surface, 0 and 8-11).
INK_CONST uint FIELD_SAMPLES = 12u;     // vec4[2 × samples]: each sample's position, then its normal (w unused)
INK_CONST uint FIELD_GRAPH = 13u;       // uint[]: the neighbours (k × points), the parents (points), the child
                                        // starts (points + 1), the children; offsets FieldParams-derived (below)
INK_CONST uint FIELD_STATE = 14u;       // vec4[2 × points]: per point (unit normal, confidence), then (seed, 0)
INK_CONST uint FIELD_DIRECTIONS = 15u;  // vec4[2 × points]: two halves of directions (xyz; w unused), ping-pong

INK_END

#endif
