// Hermite RBF implicit surface (report §6.1): fitting on the CPU and evaluation of f, ∇f and the Hessian.
//
//   f(x) = Σ_j [ α_j ψ(x − p_j) − ⟨β_j, ∇ψ(x − p_j)⟩ ] + ⟨a, x⟩ + b          (eq. 6)
//   ψ(x) = ‖x‖³,  ∇ψ(x) = 3‖x‖x,  Hψ(x) = (3/‖x‖)(‖x‖² I + x xᵀ)              (§6.1.2)
//
// The model lives in normalized coordinates (bounding-box centre at the origin, diagonal 1); the Surface's
// `frame` (surface.h) maps between them and the input's units. The GLSL twin of eval() is
// spirv_shaders/refine/hrbf.glsl.
#pragma once

#include "base/common.h"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ink {

// x_normalized = (x_input − center) · scale.
struct Frame {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double scale = 1.0;

    Eigen::Vector3d toNormalized(const Eigen::Vector3d& x) const { return (x - center) * scale; }
    Eigen::Vector3d toInput(const Eigen::Vector3d& x) const { return x / scale + center; }
    // The frame that puts the bounding box of `points` at the origin with unit diagonal.
    static Frame unitDiagonal(const std::vector<Eigen::Vector3d>& points);
};

struct Hrbf {
    std::vector<Eigen::Vector3d> centers;         // p_j (normalized)
    std::vector<double> alpha;                    // α_j
    std::vector<Eigen::Vector3d> beta;            // β_j
    std::vector<Eigen::Vector3d> normals;         // n_j, the unit normals the fit interpolates (∇f(p_j) = n_j)
    Eigen::Vector3d a = Eigen::Vector3d::Zero();  // linear term (eq. 6)
    double b = 0.0;

    size_t size() const { return centers.size(); }
    double f(const Eigen::Vector3d& x) const;
    // f and ∇f together (they share the distances); `hessian` is filled when non-null.
    double eval(const Eigen::Vector3d& x, Eigen::Vector3d& gradient, Eigen::Matrix3d* hessian = nullptr) const;
};

constexpr size_t kMaxControlPoints = 4000;  // the dense (4m+4)² system: 2 GiB and minutes beyond this

struct FitStats {
    size_t controlPoints = 0;
    double seconds = 0;
    double relativeResidual = 0;   // ‖A x − B‖ / ‖B‖ of eq. 5
    double maxDistance = 0;        // max_i |f(p_i)| / ‖∇f(p_i)‖, normalized units (= fraction of the diagonal)
    double maxNormalAngleDeg = 0;  // max_i ∠(∇f(p_i), n_i)
    double meanDistance = 0;       // mean_i |f(p_i)| / ‖∇f(p_i)‖ (filled by the .hrbf reader)
    PhaseTimes phases;             // fitModel's steps (fit --stats's `phases_ms`)
};

// Solves eq. 5 with the linear term (eq. 7–10) for points and unit normals given in normalized
// coordinates (distinct, finite), with LAPACK's symmetric-indefinite solver (docs/fitting.md). Throws
// ink::Error when there are too few points, two points coincide, a value is not finite, or the system is
// singular or too ill-conditioned to trust (relative residual above 1e-6).
Hrbf fitHrbf(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
             FitStats* stats = nullptr);

// The stats of `model` at its own centres against its stored normals (maxDistance, maxNormalAngleDeg,
// controlPoints); relativeResidual and seconds are left 0. Used for models loaded from .hrbf files.
FitStats measureFit(const Hrbf& model);

// Principal curvatures of the level set through x, from ∇f and the Hessian: κ1 ≤ κ2 with unit
// tangent directions d1 (of κ1) and d2. Sign convention: a sphere with outward gradient has κ > 0.
struct Curvature {
    double k1 = 0, k2 = 0;
    Eigen::Vector3d d1 = Eigen::Vector3d::UnitX(), d2 = Eigen::Vector3d::UnitY();
};
Curvature principalCurvatures(const Eigen::Vector3d& gradient, const Eigen::Matrix3d& hessian);

}  // namespace ink
