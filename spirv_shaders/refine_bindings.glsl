// Descriptor set shared by the three refinement passes (refine, scan, compact). See engine/refine.cpp.
#ifndef REFINE_BINDINGS_GLSL
#define REFINE_BINDINGS_GLSL

#include "common.glsl"

layout(std430, binding = 1) buffer PointBuffer { Point points[]; };
layout(std430, binding = 2) buffer CandidateBuffer { Point candidates[]; };
layout(std430, binding = 3) buffer FlagBuffer { uint flags[]; };      // 1 = kept, per candidate
layout(std430, binding = 4) buffer BlockBuffer { uint blockSums[]; };  // kept per workgroup, then its offset
layout(std430, binding = 5) buffer LevelBuffer { LevelInfo levels[MAX_LEVELS]; };
// Indirect arguments: one dispatch (x, y, z, pad) per level, then the draw (count, instances, first, 0).
layout(std430, binding = 6) buffer IndirectBuffer {
    uvec4 dispatches[MAX_LEVELS];
    uvec4 draw;
};
layout(std430, binding = 7) readonly buffer SeedBuffer { vec4 seeds[]; };  // xyz start, w parent index

layout(push_constant) uniform Params {
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
    uint childCount;     // children per parent at this level (1 for seeds)
    uint nextChildCount; // children per point at the next level (0 when this is the last)
    uint keepAll;        // 1: draw every level; 0: only the last
    float toneOffset;    // the tone value is toneOffset + toneScale·u, u uniform in [0,1): levels take
    float toneScale;     // consecutive shares of [0,1), coarse first, so that tone thins fine levels first
    uint passChildren;   // children of one pass; level 1 makes childCount / passChildren passes of them
} pc;

const uint GROUP_SIZE = 256u;

#endif
