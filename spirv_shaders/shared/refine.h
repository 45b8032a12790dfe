// The refinement's interface (refine.comp, refine_global.comp, scan.comp, compact.comp; engine/refine/refine.cpp): the
// point records, the per-level bookkeeping, the indirect arguments, the push constants, the surface's buffers
// and the descriptor set's bindings (see interface.h).
#ifndef INK_SHARED_REFINE_H
#define INK_SHARED_REFINE_H

#include "interface.h"
#include "limits.h"

INK_BEGIN

// 32 bytes a point, in normalized model coordinates (std430; engine/refine/point_record.h's PointRecord on the host).
struct Point {
    vec3 position;
    uint level;
    vec3 normal;  // unit ∇f
    float tone;   // fixed random value in [0,1): decides whether tone draws the point
};
INK_ASSERT_SIZE(Point, 32);
INK_ASSERT_OFFSET(Point, level, 12);
INK_ASSERT_OFFSET(Point, normal, 16);
INK_ASSERT_OFFSET(Point, tone, 28);

// One level's bookkeeping (std430), MAX_LEVELS of them.
struct LevelInfo {
    uint candidates;    // candidates generated at this level
    uint parentOffset;  // first parent in the point buffer
    uint keptOffset;    // first kept point in the point buffer
    uint kept;
    uint dropped[DROP_REASONS];
};
INK_ASSERT_SIZE(LevelInfo, 32);
INK_ASSERT_OFFSET(LevelInfo, kept, 12);
INK_ASSERT_OFFSET(LevelInfo, dropped, 16);

// Indirect arguments (std430): one dispatch (x, y, z, pad) per level, then the refinement's draw (count,
// instances, first, 0), then the stipple selection's.
struct IndirectArgs {
    uvec4 dispatches[MAX_LEVELS];
    uvec4 draw;
    uvec4 selectedDraw;
};
INK_ASSERT_SIZE(IndirectArgs, 16 * 16 + 32);
INK_ASSERT_OFFSET(IndirectArgs, draw, 16 * 16);
INK_ASSERT_OFFSET(IndirectArgs, selectedDraw, 16 * 16 + 16);

// The push constants of one level (std430).
struct RefineParams {
    vec4 axis;           // xyz: direction-sampling axis (unit)
    float rho;           // ρ of this level (report §4.2); 0 for seeds
    float jumpLimit;     // drop a point that ends farther than this from its parent or seed
    float eps1;          // ε₁: accept when |f|/‖∇f‖ < ε₁ (eq. 11 stop rule)
    float eps2;          // ε₂: drop when ‖∇f‖ < ε₂
    float delta;         // δ ∈ (0,1): Armijo step factor
    float phi;           // φ ∈ (0,½): Armijo sufficient decrease
    uint maxIterations;  // projection iteration cap
    uint mode;           // 0 seeds, 1 stippling, 2 direction sampling
    uint direction;      // 0 axis, 1 min curvature, 2 max curvature
    uint level;
    uint seed;
    uint childCount;      // children per parent at this level (1 for seeds)
    uint nextChildCount;  // children per point at the next level (0 when this is the last)
    uint keepAll;         // 1: draw every level; 0: only the last
    float toneOffset;     // the tone value is toneOffset + toneScale·u, u uniform in [0,1): levels take
    float toneScale;      // consecutive shares of [0,1), coarse first, so that tone thins fine levels first
    uint passChildren;    // children of one pass; level 1 makes childCount / passChildren passes of them
};
INK_ASSERT_SIZE(RefineParams, 84);
INK_ASSERT_OFFSET(RefineParams, rho, 16);
INK_ASSERT_OFFSET(RefineParams, maxIterations, 40);
INK_ASSERT_OFFSET(RefineParams, keepAll, 68);
INK_ASSERT_OFFSET(RefineParams, toneOffset, 72);
INK_ASSERT_OFFSET(RefineParams, passChildren, 80);

// The global HRBF (hrbf.glsl, std140, doubles): the header, then HRBF_BLOCKS blocks of HRBF_BLOCK_SIZE centres.
struct HrbfHeader {
    dvec4 linear;  // a, b
    uvec4 count;   // m, unused ×3
};
INK_ASSERT_SIZE(HrbfHeader, 48);
INK_ASSERT_OFFSET(HrbfHeader, count, 32);
struct HrbfCenter {
    dvec4 pAlpha;  // p_j, α_j
    dvec4 beta;    // β_j, unused
};
INK_ASSERT_SIZE(HrbfCenter, 64);
INK_ASSERT_OFFSET(HrbfCenter, beta, 32);

// The partition of unity (pu_hrbf.glsl, float): the std140 header, and the std430 patches. The nodes and the far
// field's centres are vec4 pairs (p, α), (β, 0); the cells are uints.
struct PuHeader {
    vec4 origin;        // xyz: the grid's corner; w: 1 / cell side
    uvec4 dims;         // xyz: cells along each axis; w: far-field centres
    vec4 coarseLinear;  // the far field's a, b
    vec4 params;        // x: τ
    uvec4 nodes;        // xy: the nodes' device address, low and high words (refine_large.comp; else 0)
};
INK_ASSERT_SIZE(PuHeader, 80);
INK_ASSERT_OFFSET(PuHeader, dims, 16);
INK_ASSERT_OFFSET(PuHeader, coarseLinear, 32);
INK_ASSERT_OFFSET(PuHeader, params, 48);
INK_ASSERT_OFFSET(PuHeader, nodes, 64);
struct PuPatch {
    vec4 centerRadius;  // c_i, R_i
    vec4 linear;        // a_i, b_i (patch units)
    uvec4 range;        // first node, node count
};
INK_ASSERT_SIZE(PuPatch, 48);
INK_ASSERT_OFFSET(PuPatch, linear, 16);
INK_ASSERT_OFFSET(PuPatch, range, 32);

// The refinement's descriptor set (set 0).
INK_CONST uint REFINE_SURFACE_HEADER = 0u;  // HrbfHeader or PuHeader (uniform)
INK_CONST uint REFINE_POINTS = 1u;          // Point[]
INK_CONST uint REFINE_CANDIDATES = 2u;      // Point[]
INK_CONST uint REFINE_FLAGS = 3u;           // uint[]: 1 = kept, per candidate
INK_CONST uint REFINE_BLOCKS = 4u;          // uint[]: kept per workgroup, then its offset
INK_CONST uint REFINE_LEVELS = 5u;          // LevelInfo[MAX_LEVELS]
INK_CONST uint REFINE_INDIRECT = 6u;        // IndirectArgs
INK_CONST uint REFINE_SEEDS = 7u;           // vec4[]: xyz start, w parent index
INK_CONST uint REFINE_HRBF_CENTERS = 8u;    // the global fit: HRBF_BLOCKS uniform blocks of HrbfCenter
INK_CONST uint REFINE_PU_PATCHES = 8u;      // the partition of unity: PuPatch[]
INK_CONST uint REFINE_PU_NODES = 9u;        // vec4[] (not bound for refine_large.comp: it reads them by address)
INK_CONST uint REFINE_PU_CELLS = 10u;       // uint[]: cell starts (cells + 1), then patch ids
INK_CONST uint REFINE_PU_COARSE = 11u;      // vec4[]

INK_END

#endif
