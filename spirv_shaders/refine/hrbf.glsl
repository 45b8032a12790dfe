// The HRBF evaluation on the device (report eq. 6, ψ = r³), used by refine.comp. The CPU twin is engine/surface/hrbf.cpp.
//   f(x)  = Σ_j [ α_j ψ(d) − ⟨β_j, ∇ψ(d)⟩ ] + ⟨a, x⟩ + b,   d = x − p_j, r = ‖d‖
//   ∇f(x) = Σ_j [ 3 α_j r d − 3 (r β_j + d ⟨d, β_j⟩ / r) ] + a
// Coordinates are the model's normalized ones (bounding-box diagonal 1).
//
// Double precision: the terms are large and cancel (on the bunny with 684 centres Σ|α_j| ≈ 8e4, while f near
// the surface is ~1e-6), so float arithmetic leaves |f|/‖∇f‖ noise of ~1e-3 of the diagonal, far above ε₁.
#ifndef HRBF_GLSL
#define HRBF_GLSL

#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_control_flow_attributes : require

#ifndef HRBF_SET
#define HRBF_SET 0
#endif

#include "shared/refine.h"  // HrbfHeader, HrbfCenter, HRBF_BLOCK_SIZE, HRBF_BLOCKS, the bindings
#define HRBF_TERM_DOUBLE
#include "refine/hrbf_term.glsl"

// The centres live in uniform blocks of HRBF_BLOCK_SIZE centres (64 KiB). The buffer holds whole blocks
// (engine/refine/refine.cpp), so reading past the last centre within its block is safe.
layout(std140, set = HRBF_SET, binding = REFINE_SURFACE_HEADER) uniform HrbfHeaderBlock { HrbfHeader hrbf; };

layout(std140, set = HRBF_SET, binding = REFINE_HRBF_CENTERS) uniform HrbfBlock {
    HrbfCenter centers[HRBF_BLOCK_SIZE];
} hrbfBlocks[HRBF_BLOCKS];

HrbfCenter hrbfCenter(uint j) { return hrbfBlocks[j / HRBF_BLOCK_SIZE].centers[j % HRBF_BLOCK_SIZE]; }

// v of invocation l, in every invocation. A double as two 32-bit shuffles: llvmpipe turns those into one
// vpermd each, while its subgroupBroadcast first searches for an active lane, element by element.
double hrbfLane(double v, uint l) {
    uvec2 u = unpackDouble2x32(v);
    return packDouble2x32(uvec2(subgroupShuffle(u.x, l), subgroupShuffle(u.y, l)));
}

// f and ∇f (eq. 6 and its gradient). Every invocation needs every centre, and a centre read at a loop index
// costs llvmpipe (Mesa 22.3) a per-lane gather of each double: it broadcasts a uniform load only at a
// constant or push-constant offset, never at a loop counter; ~200 instructions a centre against ~50 of
// arithmetic. So the subgroup shares the loads, each invocation reading different centres.
//
// Call it only from subgroup-uniform control flow (every invocation of the subgroup active).
double hrbfEval(dvec3 x, out dvec3 grad) {
    uint m = hrbf.count.x, lane = gl_SubgroupInvocationID;
    double f = 0.0LF;
    dvec3 g = dvec3(0.0LF);
    if (gl_SubgroupSize == 8u) {
        // Transposed (lavapipe on AVX2): invocation c takes centres j ≡ c (mod 8) against the 8 points of
        // the subgroup, and keeps a partial sum per point; subgroupAdd then gives each point its f and ∇f.
        // Broadcasting each centre to all lanes instead is as slow as the gather on llvmpipe.
        dvec3 X[8], G[8];
        double F[8];
        [[unroll]] for (uint l = 0u; l < 8u; ++l) {
            X[l] = dvec3(hrbfLane(x.x, l), hrbfLane(x.y, l), hrbfLane(x.z, l));
            F[l] = 0.0LF;
            G[l] = dvec3(0.0LF);
        }
        // 16 centres a pass: llvmpipe blends every loop-carried value with the loop mask once a pass, so two
        // centres an invocation halve that (4% faster; four are slower). 16 divides HRBF_BLOCK_SIZE, so a pass
        // stays in one block, which exists since j0 < m. Centres past m count as zeros (α = β = 0: +0).
        for (uint j0 = 0u; j0 < m; j0 += 16u) {
            [[unroll]] for (uint u = 0u; u < 2u; ++u) {
                uint j = j0 + 8u * u + lane;
                HrbfCenter c = hrbfBlocks[j0 / HRBF_BLOCK_SIZE].centers[j % HRBF_BLOCK_SIZE];
                dvec4 pa = j < m ? c.pAlpha : dvec4(0.0LF);
                dvec3 beta = j < m ? c.beta.xyz : dvec3(0.0LF);
                [[unroll]] for (uint l = 0u; l < 8u; ++l) hrbfAddFused(X[l], pa, beta, F[l], G[l]);
            }
        }
        [[unroll]] for (uint l = 0u; l < 8u; ++l) {
            double fl = subgroupAdd(F[l]);
            dvec3 gl = dvec3(subgroupAdd(G[l].x), subgroupAdd(G[l].y), subgroupAdd(G[l].z));
            if (lane == l) {
                f = fl;
                g = gl;
            }
        }
    } else {
        // Any other subgroup size: chunks of gl_SubgroupSize centres, one loaded by each invocation and
        // broadcast to all (a dynamically uniform id, allowed from SPIR-V 1.5), summed in order j = 0..m−1.
        // A power of two ≤ 128, the subgroup size divides HRBF_BLOCK_SIZE, so a chunk stays in one block.
        for (uint j0 = 0u; j0 < m; j0 += gl_SubgroupSize) {
            HrbfCenter c = hrbfBlocks[j0 / HRBF_BLOCK_SIZE].centers[(j0 + lane) % HRBF_BLOCK_SIZE];
            uint n = min(gl_SubgroupSize, m - j0);
            for (uint k = 0u; k < n; ++k)
                hrbfAddFused(x, subgroupBroadcast(c.pAlpha, k), subgroupBroadcast(c.beta.xyz, k), f, g);
        }
    }
    grad = hrbf.linear.xyz + 3.0LF * g;
    return dot(hrbf.linear.xyz, x) + hrbf.linear.w + f;
}

// f, ∇f and the Hessian (for principal curvature directions). Per invocation, callable anywhere.
double hrbfEvalHessian(dvec3 x, out dvec3 grad, out dmat3 H) {
    double f = dot(hrbf.linear.xyz, x) + hrbf.linear.w;
    dvec3 g = hrbf.linear.xyz;
    dmat3 h = dmat3(0.0LF);
    uint m = hrbf.count.x;
    for (uint j = 0u; j < m; ++j) {
        HrbfCenter c = hrbfCenter(j);
        hrbfNodeHessianD(x, c.pAlpha, c.beta.xyz, f, g, h);
    }
    grad = g;
    H = h;
    return f;
}

#endif
