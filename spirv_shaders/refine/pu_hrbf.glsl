// The partition-of-unity HRBF on the device, in float (engine/surface/pu_hrbf.h; its CPU twin is PuFloat):
//   F(x) = (Σ w_i f_i + w_c f_c) / (Σ w_i + w_c)                                  (PU blend, far field)
//   f_i(x) = R_i h_i(q),  q = (x − c_i)/R_i,  h_i(q) = Σ_j [α_j ψ(q − p_j) − ⟨β_j, ∇ψ(q − p_j)⟩] + ⟨a_i, q⟩ + b_i
//   w_i = W(‖q‖), W(d) = (1 − d)⁴ (4d + 1);  w_c = τ (1 − S/τ)³ for S = Σ w_i < τ
// The local coefficients are of order one, so float keeps |f|/‖∇f‖ within ~1e-8 of the diagonal (docs/fitting.md).
//
// Each invocation walks the patches of its own grid cell and their nodes. On lavapipe too: a kernel whose
// subgroup of 8 shared the node loads (each lane loading every eighth node and evaluating it against all 8
// points) was slower than this loop with patches of 8-24 nodes, 1.8x on the bunny and 2.7x on the armadillo
// (docs/performance.md), and was removed.
#ifndef PU_HRBF_GLSL
#define PU_HRBF_GLSL

#include "shared/refine.h"  // PuHeader, PuPatch, the bindings
#include "refine/hrbf_term.glsl"

layout(std140, binding = REFINE_SURFACE_HEADER) uniform PuHeaderBlock { PuHeader pu; };
layout(std430, binding = REFINE_PU_PATCHES) readonly buffer PuPatches { PuPatch puPatches[]; };
// Per node: (p_j, α_j), (β_j, 0). A model whose nodes outgrow one storage buffer's range (maxStorageBufferRange:
// 128 MiB on lavapipe, a scan of 10⁶ points has 222 MiB) reads them by device address (refine_large.comp).
#ifdef PU_NODES_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer PuNodeArray { vec4 v[]; };
#define PU_NODE(k) PuNodeArray(pu.nodes.xy).v[k]
#else
layout(std430, binding = REFINE_PU_NODES) readonly buffer PuNodes { vec4 puNodes[]; };
#define PU_NODE(k) puNodes[k]
#endif
layout(std430, binding = REFINE_PU_CELLS) readonly buffer PuCells { uint puCells[]; };  // cell starts (cells + 1), then patch ids
layout(std430, binding = REFINE_PU_COARSE) readonly buffer PuCoarse { vec4 puCoarse[]; };  // per centre: (p, α), (β, 0)

// The grid cell of x, or −1 outside the grid.
int puCell(vec3 x) {
    vec3 u = (x - pu.origin.xyz) * pu.origin.w;
    if (!(min(u.x, min(u.y, u.z)) >= 0.0) || !all(lessThan(u, vec3(pu.dims.xyz)))) return -1;
    uvec3 i = uvec3(u);
    return int(i.x + pu.dims.x * (i.y + pu.dims.y * i.z));
}

uint puCellCount() { return pu.dims.x * pu.dims.y * pu.dims.z; }

// The Wendland weight of a patch at q (‖q‖ < 1) and its gradient in x: ∇w = −20 (1 − d)³ q / R.
float puWeight(vec3 q, float radius, out vec3 dw) {
    float d = length(q), e = 1.0 - d, e2 = e * e;
    dw = (-20.0 * e2 * e / radius) * q;
    return e2 * e2 * (4.0 * d + 1.0);
}

// The far field f_c, a global HRBF in normalized coordinates (its sum is short and only read off the surface).
float puFar(vec3 x, out vec3 g) {
    float f = dot(pu.coarseLinear.xyz, x) + pu.coarseLinear.w;
    g = pu.coarseLinear.xyz;
    for (uint j = 0u; j < pu.dims.w; ++j) hrbfNodeF(x, puCoarse[2u * j], puCoarse[2u * j + 1u].xyz, f, g);
    return f;
}

// F = N / S, ∇F = (∇N − F ∇S) / S, with the far field blended in where S < τ.
float puFinish(vec3 x, float S, vec3 dS, float N, vec3 dN, out vec3 grad) {
    float tau = pu.params.x;
    if (S < tau) {
        float e = 1.0 - S / tau, wc = tau * e * e * e;
        vec3 dwc = -3.0 * e * e * dS, gc;
        float fc = puFar(x, gc);
        S += wc;
        N += wc * fc;
        dN += fc * dwc + wc * gc;
        dS += dwc;
    }
    float F = N / S;
    grad = (dN - F * dS) / S;
    return F;
}

// F and ∇F: the patches of x's cell, each with its nodes.
float puEval(vec3 x, out vec3 grad) {
    float S = 0.0, N = 0.0;
    vec3 dS = vec3(0.0), dN = vec3(0.0);
    int cell = puCell(x);
    if (cell >= 0) {
        uint base = puCellCount() + 1u, k1 = puCells[cell + 1];
        for (uint k = puCells[cell]; k < k1; ++k) {
            PuPatch P = puPatches[puCells[base + k]];
            float R = P.centerRadius.w;
            vec3 q = (x - P.centerRadius.xyz) / R;
            if (!(dot(q, q) < 1.0)) continue;
            float h = dot(P.linear.xyz, q) + P.linear.w;
            vec3 g = P.linear.xyz;
            uint j1 = P.range.x + P.range.y;
            for (uint j = P.range.x; j < j1; ++j) hrbfNodeF(q, PU_NODE(2u * j), PU_NODE(2u * j + 1u).xyz, h, g);
            vec3 dw;
            float w = puWeight(q, R, dw), fi = R * h;
            S += w;
            dS += dw;
            N += w * fi;
            dN += fi * dw + w * g;
        }
    }
    return puFinish(x, S, dS, N, dN, grad);
}

// The sums the Hessian is made of, over the patches: S, N = Σ w_i f_i, their gradients and Hessians.
struct PuHessianSums {
    float S, N;
    vec3 dS, dN;
    mat3 HS, HN;
};

PuHessianSums puNoSums() { return PuHessianSums(0.0, 0.0, vec3(0.0), vec3(0.0), mat3(0.0), mat3(0.0)); }

// Patch `patchId`'s terms at x, added to s (nothing outside its ball).
void puAddPatchHessian(uint patchId, vec3 x, inout PuHessianSums s) {
    PuPatch P = puPatches[patchId];
    float R = P.centerRadius.w;
    vec3 q = (x - P.centerRadius.xyz) / R;
    if (!(dot(q, q) < 1.0)) return;
    float h = dot(P.linear.xyz, q) + P.linear.w;
    vec3 g = P.linear.xyz;
    mat3 Hh = mat3(0.0);
    uint j1 = P.range.x + P.range.y;
    for (uint j = P.range.x; j < j1; ++j) hrbfNodeHessianF(q, PU_NODE(2u * j), PU_NODE(2u * j + 1u).xyz, h, g, Hh);
    vec3 dw;
    float w = puWeight(q, R, dw), fi = R * h;
    float d = length(q), e = 1.0 - d, e2 = e * e;
    mat3 Hw = mat3(e2 * e);  // Hw = −20/R² [(1 − d)³ I − 3 (1 − d)² q qᵀ / d]
    if (d > 0.0) Hw -= (3.0 * e2 / d) * outerProduct(q, q);
    Hw *= -20.0 / (R * R);
    s.S += w;
    s.N += w * fi;
    s.dS += dw;
    s.dN += fi * dw + w * g;
    s.HS += Hw;
    s.HN += fi * Hw + outerProduct(dw, g) + outerProduct(g, dw) + (w / R) * Hh;
}

// F, ∇F and HF from the patches' sums and, where S < τ, the far field's value, gradient and Hessian at x.
float puFinishHessian(vec3 x, PuHessianSums s, float fc, vec3 gc, mat3 Hc, out vec3 grad, out mat3 H) {
    float tau = pu.params.x;
    if (s.S < tau) {
        float e = 1.0 - s.S / tau, wc = tau * e * e * e;
        vec3 dwc = -3.0 * e * e * s.dS;
        mat3 Hwc = (6.0 * e / tau) * outerProduct(s.dS, s.dS) - 3.0 * e * e * s.HS;
        s.S += wc;
        s.N += wc * fc;
        s.dN += fc * dwc + wc * gc;
        s.HN += fc * Hwc + outerProduct(dwc, gc) + outerProduct(gc, dwc) + wc * Hc;
        s.HS += Hwc;
        s.dS += dwc;
    }
    float F = s.N / s.S;
    grad = (s.dN - F * s.dS) / s.S;
    H = (s.HN - outerProduct(grad, s.dS) - outerProduct(s.dS, grad) - F * s.HS) / s.S;
    return F;
}

// F, ∇F and the Hessian HF = (HN − ∇F ∇Sᵀ − ∇S ∇Fᵀ − F HS) / S.
float puEvalHessian(vec3 x, out vec3 grad, out mat3 H) {
    PuHessianSums s = puNoSums();
    int cell = puCell(x);
    if (cell >= 0) {
        uint base = puCellCount() + 1u, k1 = puCells[cell + 1];
        for (uint k = puCells[cell]; k < k1; ++k) puAddPatchHessian(puCells[base + k], x, s);
    }
    float fc = dot(pu.coarseLinear.xyz, x) + pu.coarseLinear.w;
    vec3 gc = pu.coarseLinear.xyz;
    mat3 Hc = mat3(0.0);
    if (s.S < pu.params.x)
        for (uint j = 0u; j < pu.dims.w; ++j) hrbfNodeHessianF(x, puCoarse[2u * j], puCoarse[2u * j + 1u].xyz, fc, gc, Hc);
    return puFinishHessian(x, s, fc, gc, Hc, grad, H);
}

#endif
