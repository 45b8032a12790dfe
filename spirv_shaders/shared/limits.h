// Workgroup sizes, limits, and the bits and codes that the device writes and the host reads (see interface.h).
#ifndef INK_SHARED_LIMITS_H
#define INK_SHARED_LIMITS_H

#include "interface.h"

INK_BEGIN

// Workgroup sizes: every compute pass's `local_size_x`, and what the host divides its dispatches by.
INK_CONST uint GROUP_SIZE = 256u;       // refine, scan, compact, splat, stamp, lines, the selection's passes
INK_CONST uint PHASE_GROUP_SIZE = 64u;  // select_phase.comp: one invocation per bucket of a phase

// The refinement: seeds + 15 refinement levels.
INK_CONST uint MAX_LEVELS = 16u;
// Why a candidate was dropped: LevelInfo::dropped's index (DropReason in engine/refine/refine_plan.h names them).
INK_CONST uint DROP_GRADIENT = 0u;    // ‖∇f‖ < ε₂
INK_CONST uint DROP_ARMIJO = 1u;      // i_k > 16
INK_CONST uint DROP_ITERATIONS = 2u;  // iteration cap reached
INK_CONST uint DROP_JUMP = 3u;        // moved too far from its parent (another sheet)
INK_CONST uint DROP_REASONS = 4u;

// The global HRBF's centres (hrbf.glsl): uniform blocks of HRBF_BLOCK_SIZE centres (64 KiB), HRBF_BLOCKS of
// them; HRBF_BLOCK_SIZE × HRBF_BLOCKS ≥ kMaxControlPoints (engine/surface/hrbf.h).
INK_CONST uint HRBF_BLOCK_SIZE = 1024u;
INK_CONST uint HRBF_BLOCKS = 4u;

// The HRBF node term's Hessian (hrbf_term.glsl, engine/surface/r3_term.h): the part of it that comes from β (the third
// derivative of ψ = r³) is bounded but depends on the direction of x − p alone, so it jumps at the node, and near
// the node float rounding of x − p picks that direction: curvature there was noise, and differed by device. It
// fades in as (r / R3_HESSIAN_FADE)² within R3_HESSIAN_FADE of the node (in the node's coordinates: a patch's
// radius is 1), and at the node takes its average over directions, 0.
INK_CONST float R3_HESSIAN_FADE = 1e-3;

// The stipple selection's stages (kMaxSelectStages in engine/select/select_plan.h).
INK_CONST uint MAX_STAGES = 48u;

// The frame's coverage: four bits a pixel, eight pixels a word (pixel i: word i >> 3, bits 4·(i & 7)).
INK_CONST uint INK_BIT = 1u;      // a dot's or hatching's ink
INK_CONST uint HIDDEN_BIT = 2u;   // hidden ink (occluded silhouettes, hidden contours)
INK_CONST uint HALO_BIT = 4u;     // a contour's halo (paper)
INK_CONST uint CONTOUR_BIT = 8u;  // a visible contour's ink
INK_CONST uint COVERAGE_SHIFT = 3u;
INK_CONST uint COVERAGE_BITS = 4u;
// The splat depth of an empty cell: FLT_MAX's bits (positive floats order as their bits do).
INK_CONST uint FAR_DEPTH = 0x7F7FFFFFu;

// Pen lines: a traced segment's kind bits (KIND_HATCH, family << HATCH_FAMILY_SHIFT (2 bits: 0 along the field,
// 1 across it, 2 diagonal), level << HATCH_LEVEL_SHIFT; KIND_CREASE, KIND_BOUNDARY; contours none or KIND_OCCLUDED),
// and a drawn segment's flags.
INK_CONST uint KIND_HATCH = 1u;
INK_CONST uint HATCH_FAMILY_SHIFT = 1u;
INK_CONST uint HATCH_LEVEL_SHIFT = 3u;
INK_CONST uint KIND_CREASE = 16u;
INK_CONST uint KIND_BOUNDARY = 32u;
// A contour piece its own surface hides (PenStroke::occluded); a crease of a closed part, hidden where both its
// faces turn away (PenStroke::faced).
INK_CONST uint KIND_OCCLUDED = 64u;
INK_CONST uint KIND_FACED = 128u;
// A crease shows only where one of its faces turns towards the eye, n·v above −FACING_SLACK (lines.comp).
INK_CONST float FACING_SLACK = 0.02;
// Every segment also carries how many segments of its stroke lie before it (bits 8–15) and after it (bits 16–23),
// each clamped to SEG_REACH: lines.comp walks along a hatching stroke to measure the run a segment is in, and
// lines_runs.comp along a contour, crease or boundary line for the visibility around a segment.
INK_CONST uint SEG_BEFORE_SHIFT = 8u;
INK_CONST uint SEG_AFTER_SHIFT = 16u;
INK_CONST uint SEG_REACH = 255u;
INK_CONST uint SEG_VISIBLE = 1u;
INK_CONST uint SEG_HIDDEN = 2u;
INK_CONST uint SEG_INTERIOR = 4u;
// DrawSegment::segment: the traced segment's index, and lines.comp's own decision for lines_runs.comp.
INK_CONST uint SEG_INDEX_MASK = 0x3FFFFFFFu;
INK_CONST uint SEG_RAW_SHOWN = 0x40000000u;    // in front of the camera and in the image
INK_CONST uint SEG_RAW_VISIBLE = 0x80000000u;  // not behind the surface (and a crease's face towards the eye)

INK_END

#endif
