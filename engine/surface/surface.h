// The fitted implicit surface the rest of the engine draws: a partition-of-unity HRBF (pu_hrbf.h, the default)
// or the report's single dense HRBF (hrbf.h, `--fit global`), in normalized coordinates (Frame), with the
// oriented points it interpolates.
#pragma once

#include "surface/hrbf.h"
#include "surface/pu_hrbf.h"

#include <Eigen/Core>
#include <vector>

namespace ink {

enum class FitMethod { PartitionOfUnity, Global };

struct Surface {
    FitMethod method = FitMethod::PartitionOfUnity;
    Hrbf global;  // method == Global
    PuHrbf pu;    // method == PartitionOfUnity
    Frame frame;
    std::vector<Eigen::Vector3d> centers;  // the interpolated points (normalized): f(p) = 0, ∇f(p) = n
    std::vector<Eigen::Vector3d> normals;  // their unit normals
    std::vector<Eigen::Vector3d> seeds;    // a well-spread subset of at most kMaxSeeds centres (refinement seeds)

    size_t size() const { return centers.size(); }
    double eval(const Eigen::Vector3d& x, Eigen::Vector3d& gradient, Eigen::Matrix3d* hessian = nullptr) const {
        return method == FitMethod::Global ? global.eval(x, gradient, hessian) : pu.eval(x, gradient, hessian);
    }
    double f(const Eigen::Vector3d& x) const {
        Eigen::Vector3d g;
        return eval(x, g);
    }
};

// The refinement starts from at most this many of the interpolated points (farthest-point samples): the
// drawing's density comes from the refinement, not from how dense the input is.
constexpr size_t kMaxSeeds = 1000;

// Fills `seeds` from `centers`.
void chooseSeeds(Surface& surface);

// The stats of `surface` at its own centres against its normals, evaluated as the device evaluates it (float for
// the partition of unity, double for the global fit): controlPoints, maxDistance, maxNormalAngleDeg.
FitStats measureFit(const Surface& surface);
// The same from the values (∇f, f) at every centre, in float as PuFloat::evalMany gives them.
FitStats measureFit(const Surface& surface, const std::vector<Eigen::Vector4f>& values);

}  // namespace ink
