// The HRBF's node term (report eq. 6, ψ(r) = r³) and its derivatives, the one place the host writes them
// (spirv_shaders/refine/hrbf_term.glsl is the device's). For a node (p, α, β) at d = q − p, r = ‖d‖:
//   term      α r³ − 3 r ⟨d, β⟩                                  (α ψ(d) − ⟨β, ∇ψ(d)⟩)
//   gradient  3 α r d − 3 (r β + d ⟨d, β⟩ / r)
//   Hessian   3 α (r I + d dᵀ / r) − (3 / r) (β dᵀ + d βᵀ + ⟨d, β⟩ I − d dᵀ ⟨d, β⟩ / r²)
// The Hessian's β part (the third derivative of ψ contracted with β) depends on the direction of d alone, so
// it fades in within R3_HESSIAN_FADE of the node (spirv_shaders/shared/limits.h says why).
#pragma once

#include "shared/limits.h"

#include <Eigen/Core>

namespace ink {

template <class T>
inline __attribute__((always_inline)) void addR3Node(const Eigen::Matrix<T, 3, 1>& q, const Eigen::Matrix<T, 3, 1>& p,
                                                     T alpha, const Eigen::Matrix<T, 3, 1>& beta, T& f,
                                                     Eigen::Matrix<T, 3, 1>& g, Eigen::Matrix<T, 3, 3>* H) {
    const Eigen::Matrix<T, 3, 1> d = q - p;
    const T r = d.norm(), db = beta.dot(d);
    f += alpha * r * r * r - T(3) * r * db;
    if (r == T(0)) return;  // ∇ψ, Hψ and their derivatives vanish at the node
    g += T(3) * alpha * r * d - T(3) * (r * beta + d * (db / r));
    if (H) {
        // The Hessian above with its terms gathered: cI I + cdd d dᵀ + cbd (β dᵀ + d βᵀ), summed entry by entry
        // (the tracers evaluate it at every step: a third of the cost of the matrix expressions).
        const T fade = std::min(r * r / T(gpu::R3_HESSIAN_FADE * gpu::R3_HESSIAN_FADE), T(1));
        const T inverse = T(1) / r, fadeDb = fade * db * inverse;
        const T cI = T(3) * (alpha * r - fadeDb), cdd = T(3) * inverse * (alpha + fadeDb * inverse),
                cbd = T(-3) * fade * inverse;
        for (int j = 0; j < 3; ++j)
            for (int i = j; i < 3; ++i) {
                const T v = cdd * d[i] * d[j] + cbd * (beta[i] * d[j] + d[i] * beta[j]);
                (*H)(i, j) += i == j ? v + cI : v;
                if (i != j) (*H)(j, i) += v;
            }
    }
}

}  // namespace ink
