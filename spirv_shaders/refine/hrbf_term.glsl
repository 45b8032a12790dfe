// The HRBF's node term (report eq. 6, ψ(r) = r³) and its derivatives: the one place the device writes them
// (engine/surface/hrbf.cpp is the host's). For a node (p, α, β) at d = x − p, r = ‖d‖:
//   term      α r³ − 3 r ⟨d, β⟩
//   gradient  3 (α r − ⟨d, β⟩ / r) d − 3 r β
//   Hessian   3 α (r I + d dᵀ / r) − (3 / r) (β dᵀ + d βᵀ + ⟨d, β⟩ I − d dᵀ ⟨d, β⟩ / r²), the β part faded in
//             within R3_HESSIAN_FADE of the node (shared/limits.h says why)
// INK_R3_NODE(T, V4, V, M, S) writes them for one precision (scalar T, vectors V4 and V, matrix M), as
//   void hrbfNodeS(V x, V4 pa, V beta, inout T f, inout V g)                 f and ∇f
//   void hrbfNodeHessianS(V x, V4 pa, V beta, inout T f, inout V g, inout M H)  f, ∇f and the Hessian
// with pa = (p, α); the float versions (suffix F) serve the partition of unity (pu_hrbf.glsl), the double ones
// (suffix D) the global fit (hrbf.glsl). hrbfAddFused is the global fit's hot loop: the same term and gradient
// (divided by 3) rearranged into fused multiply-adds, for double precision only.
#ifndef HRBF_TERM_GLSL
#define HRBF_TERM_GLSL

#include "shared/limits.h"  // R3_HESSIAN_FADE

#define INK_R3_NODE(T, V4, V, M, S)                                                                  \
    void hrbfNode##S(V x, V4 pa, V beta, inout T f, inout V g) {                                     \
        V d = x - pa.xyz;                                                                            \
        T r = length(d), db = dot(d, beta);                                                          \
        f += pa.w * r * r * r - T(3.0) * r * db;                                                     \
        T inv = r > T(0.0) ? T(1.0) / r : T(0.0);                                                    \
        g += T(3.0) * (pa.w * r - db * inv) * d - T(3.0) * r * beta;                                 \
    }                                                                                                \
    void hrbfNodeHessian##S(V x, V4 pa, V beta, inout T f, inout V g, inout M H) {                   \
        V d = x - pa.xyz;                                                                            \
        T r = length(d), db = dot(d, beta);                                                          \
        f += pa.w * r * r * r - T(3.0) * r * db;                                                     \
        if (r == T(0.0)) return;                                                                     \
        g += T(3.0) * pa.w * r * d - T(3.0) * (r * beta + d * (db / r));                             \
        M ddT = outerProduct(d, d);                                                                  \
        H += T(3.0) * pa.w * (r * M(1.0) + ddT / r);                                                 \
        T fade = min(r * r / T(R3_HESSIAN_FADE * R3_HESSIAN_FADE), T(1.0));                         \
        H -= (fade * T(3.0) / r) *                                                                   \
             (outerProduct(beta, d) + outerProduct(d, beta) + db * M(1.0) - ddT * (db / (r * r)));   \
    }

INK_R3_NODE(float, vec4, vec3, mat3, F)

#ifdef HRBF_TERM_DOUBLE
INK_R3_NODE(double, dvec4, dvec3, dmat3, D)

// The term added to f, and the gradient divided by 3 to g:  α r³ − 3 r ⟨d, β⟩  and  (α r − ⟨d, β⟩/r) d − r β.
void hrbfAddFused(dvec3 x, dvec4 pa, dvec3 beta, inout double f, inout dvec3 g) {
    dvec3 d = x - pa.xyz;
    double r2 = fma(d.z, d.z, fma(d.y, d.y, d.x * d.x));
    double db = fma(d.z, beta.z, fma(d.y, beta.y, d.x * beta.x));
    double r = sqrt(r2);
    // At r = 0 the gradient terms vanish; max() keeps 1/r finite there without a branch.
    double s = fma(pa.w, r, -db / max(r, 1e-300LF));
    f = fma(r, fma(pa.w, r2, -3.0LF * db), f);
    g = fma(dvec3(s), d, fma(dvec3(-r), beta, g));
}
#endif

#endif
