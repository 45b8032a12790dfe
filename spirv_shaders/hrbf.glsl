// HRBF evaluation shared by every shader (report eq. 6, ψ = r³). The CPU twin is engine/hrbf.cpp.
//   f(x)  = Σ_j [ α_j ψ(d) − ⟨β_j, ∇ψ(d)⟩ ] + ⟨a, x⟩ + b,   d = x − p_j, r = ‖d‖
//   ∇f(x) = Σ_j [ 3 α_j r d − 3 (r β_j + d ⟨d, β_j⟩ / r) ] + a
// Coordinates are the model's normalized ones (bounding-box diagonal 1).
//
// Double precision: the terms are large and cancel (on the bunny with 684 centres Σ|α_j| ≈ 8e4, while f near
// the surface is ~1e-6), so float arithmetic leaves |f|/‖∇f‖ noise of ~1e-3 of the diagonal, far above ε₁.
#ifndef HRBF_GLSL
#define HRBF_GLSL

#ifndef HRBF_SET
#define HRBF_SET 0
#endif
#ifndef HRBF_BINDING
#define HRBF_BINDING 0
#endif

// The centres live in uniform blocks rather than a storage buffer: every invocation reads the same centre at
// the same time, and uniform loads are broadcast (on lavapipe this made the refinement 7× faster than the
// same loop over a storage buffer). Blocks of 1024 centres (64 KiB); HRBF_BLOCKS × 1024 ≥ kMaxControlPoints.
const uint HRBF_BLOCK_SIZE = 1024u;
const uint HRBF_BLOCKS = 4u;

struct HrbfCenter {
    dvec4 pAlpha;  // p_j, α_j
    dvec4 beta;    // β_j, unused
};

layout(std140, set = HRBF_SET, binding = HRBF_BINDING) uniform HrbfHeader {
    dvec4 linear;  // a, b
    uvec4 count;   // m, unused ×3
} hrbf;

layout(std140, set = HRBF_SET, binding = HRBF_BINDING + 8) uniform HrbfBlock {
    HrbfCenter centers[HRBF_BLOCK_SIZE];
} hrbfBlocks[HRBF_BLOCKS];

HrbfCenter hrbfCenter(uint j) { return hrbfBlocks[j / HRBF_BLOCK_SIZE].centers[j % HRBF_BLOCK_SIZE]; }

// f and ∇f (eq. 6 and its gradient).
double hrbfEval(dvec3 x, out dvec3 grad) {
    double f = dot(hrbf.linear.xyz, x) + hrbf.linear.w;
    dvec3 g = hrbf.linear.xyz;
    uint m = hrbf.count.x;
    for (uint j = 0u; j < m; ++j) {
        HrbfCenter c = hrbfCenter(j);
        dvec4 pa = c.pAlpha;
        dvec3 beta = c.beta.xyz;
        dvec3 d = x - pa.xyz;
        double r = length(d);
        double db = dot(d, beta);
        f += pa.w * r * r * r - 3.0LF * r * db;
        // At r = 0 the gradient terms vanish; max() keeps 1/r finite there without a branch.
        g += 3.0LF * pa.w * r * d - 3.0LF * (r * beta + d * (db / max(r, 1e-300LF)));
    }
    grad = g;
    return f;
}

// f, ∇f and the Hessian (for principal curvature directions).
double hrbfEvalHessian(dvec3 x, out dvec3 grad, out dmat3 H) {
    double f = dot(hrbf.linear.xyz, x) + hrbf.linear.w;
    dvec3 g = hrbf.linear.xyz;
    dmat3 h = dmat3(0.0LF);
    uint m = hrbf.count.x;
    for (uint j = 0u; j < m; ++j) {
        HrbfCenter c = hrbfCenter(j);
        dvec4 pa = c.pAlpha;
        dvec3 beta = c.beta.xyz;
        dvec3 d = x - pa.xyz;
        double r = length(d);
        double db = dot(d, beta);
        f += pa.w * r * r * r - 3.0LF * r * db;
        if (r > 0.0LF) {
            g += 3.0LF * pa.w * r * d - 3.0LF * (r * beta + d * (db / r));
            dmat3 ddT = outerProduct(d, d);
            h += 3.0LF * pa.w * (r * dmat3(1.0LF) + ddT / r);
            h -= (3.0LF / r) * (outerProduct(beta, d) + outerProduct(d, beta) + db * dmat3(1.0LF) - ddT * (db / (r * r)));
        }
    }
    grad = g;
    H = h;
    return f;
}

#endif
