// The partition-of-unity HRBF (docs/fitting.md): many small r³ + linear HRBFs, each fitted in its own frame to
// the points inside its spherical support, blended by Wendland weights that sum to one.
//
//   F(x)   = Σ_i w_i(x) f_i(x) / Σ_i w_i(x)                                           (PU blend)
//   f_i(x) = R_i · h_i((x − c_i) / R_i)        h_i: an HRBF of eq. 6 in the unit ball of patch i
//   w_i(x) = W(‖x − c_i‖ / R_i),   W(d) = (1 − d)⁴ (4d + 1) for d < 1, else 0            (Wendland C²)
//
// At a data point every f_i covering it is 0 with ∇f_i = n, so F = 0 and ∇F = n: the blend interpolates. Where
// the patches' weights fade out (far from the data) a coarse global HRBF on a subsample takes over:
//
//   F = (Σ w_i f_i + w_c f_c) / (Σ w_i + w_c),   w_c = τ (1 − S/τ)³ for S = Σ w_i < τ, else 0   (far field)
//
// τ is below the weight every data point gets from the patch of its own octree cell, so w_c = 0 at the data.
// The local coefficients are of order one (patch units), so F evaluates accurately in float: the device does
// (pu_hrbf.glsl); PuFloat here is its CPU twin, and PuHrbf::eval the double-precision model.
#pragma once

#include "surface/hrbf.h"

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ink {

struct PuPatch {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();  // c_i (normalized coordinates)
    double radius = 1;                                 // R_i
    uint32_t first = 0, count = 0;                     // its nodes: PuHrbf::nodes[first, first + count)
    Eigen::Vector3d a = Eigen::Vector3d::Zero();       // h_i's linear term ⟨a, q⟩ + b (eq. 6), patch units
    double b = 0;
};

struct PuNode {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();  // p_j in patch units: (p − c_i) / R_i, inside the unit ball
    double alpha = 0;
    Eigen::Vector3d beta = Eigen::Vector3d::Zero();
};

// Which patches can reach a point: a uniform grid over the supports' box, each cell listing the patches whose
// ball meets it (cellStart has cells + 1 entries into cellPatches). Points outside the grid meet no patch.
struct PuGrid {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double cell = 1;
    Eigen::Vector3i dims = Eigen::Vector3i::Zero();
    std::vector<uint32_t> cellStart, cellPatches;

    // The cell holding x, or −1 outside the grid.
    int64_t cellOf(const Eigen::Vector3d& x) const;
};

struct PuHrbf {
    std::vector<PuPatch> patches;
    std::vector<PuNode> nodes;
    PuGrid grid;
    Hrbf coarse;     // the far field: a global HRBF on a subsample (normalized coordinates)
    double tau = 0;  // τ of the far-field weight

    double eval(const Eigen::Vector3d& x, Eigen::Vector3d& gradient, Eigen::Matrix3d* hessian = nullptr) const;
    // S = Σ w_i(x), the patches' weight at x before the far field: below τ the far field blends in, and its zero
    // set away from the data is no surface (Model::holds).
    double patchWeight(const Eigen::Vector3d& x) const;
};

// The most nodes a patch may hold, loaded (hrbf_io.h) or grown to minPatch points in a fit: a fit makes 12 to a few
// dozen (PuOptions::minPatch, maxPatch); every evaluation near a patch visits all of them, so a 65,000-node patch
// took 78 s to render.
constexpr size_t kMaxPatchNodes = 1024;

struct PuOptions {
    // Small patches keep the local coefficients small, and so the float evaluation accurate: on the bunny with its
    // face samples the worst distance at the points was 1.0e-6 of the diagonal with these at 6, 1.4, 12, 40 and
    // 2.1e-7 at 4, 1.3, 8, 24 (the angle 0.024° and 0.003°; docs/fitting.md); `fit bunny.obj` gives 4.6e-7 and
    // 0.0037° with minPatch 12.
    size_t leafPoints = 4;  // an octree cell with more points is split
    double overlap = 1.3;   // R_i = overlap · the cell's half diagonal
    // A support with fewer points grows until it has this many. Patches of few points extrapolate where a scan's
    // random spacing leaves them thin, and the blend then folds: on a bumpy torus of 10⁵ random points, 1077 of
    // 2.7 million refined points had normals over 10° off the true surface's with 8, 299 with 10, 17 with 12, 1
    // with 14; the bunny's contour 100 cusps with 8, 56 with 12. The fit takes 1.4-1.5 times as long with 12 on 2
    // cores, 1.1-1.3 on 16 (docs/fitting.md).
    size_t minPatch = 12;
    size_t maxPatch = 24;  // a cell whose support holds more is split (while it can be)
    // Points of the far-field HRBF: more for a large fit, whose thin parts the far field must follow where the
    // patches' weights fade beside them (below τ): with 256, the fit of the Spider's 30,869 points left pieces of
    // surface beside its legs, 98.4% of the refined points within 1% of the diagonal of the mesh, 99.4% with 384,
    // 99.7% with 512 (docs/fitting.md). The cost grows as the cube: 4 × 384 + 4 unknowns, 3.4 times 256's.
    size_t coarsePoints = 256;
    size_t coarsePointsLarge = 384;
    size_t largeFit = 8192;  // points above which a fit is large
};

// How much the blend's seams add to the surface's normal and curvature (issue 24's seam figure), at points on
// F = 0 between neighbouring data points, where patches disagree most. With normalized weights W_i = w_i / Σw,
//   ∇F = Σ W_i ∇f_i + Σ ∇W_i f_i,   HF = Σ W_i Hf_i + Σ (HW_i f_i + ∇W_i ∇f_iᵀ + ∇f_i ∇W_iᵀ),
// the first sums being the patches' own shape (inside) and the rest what their disagreement puts in through the
// weights' derivatives (the seams). Reported: the angle between ∇F and Σ W_i ∇f_i, and the seams' shape operator
// (P HF P − P Σ W_i Hf_i P) / ‖∇F‖ against the patches' own, by its largest tangent eigenvalue.
struct PuSeams {
    size_t samples = 0;
    double normalDegMedian = 0, normalDegP95 = 0;            // the seams' tilt of the normal, degrees
    double curvatureRatioMedian = 0, curvatureRatioP95 = 0;  // |κ| of the seams over |κ| of the patches
    // The roughness inside: ‖S(mid) − (S(a) + S(b))/2‖ / (mean ‖S‖ + 1), S the shape operator, between
    // neighbouring data points a and b (1 in normalized units: a surface curving like a ball of the diagonal).
    double roughnessMedian = 0, roughnessP95 = 0;
};

struct PuStats {
    size_t patches = 0, minPatch = 0, maxPatch = 0;
    double meanPatch = 0;
    double maxRelativeResidual = 0;  // the worst patch's ‖A x − B‖ / ‖B‖
    size_t coarsePoints = 0;
    size_t gridCells = 0, gridEntries = 0;
    PuSeams seams;  // measured by fitModel on its final fit, not here (its rounds refit)
};

PuSeams measureSeams(const PuHrbf& model, size_t maxSamples = 4000);

// The grid of `patches` (PuHrbf::grid), a function of the patches alone: a loaded model rebuilds it.
PuGrid buildPuGrid(const std::vector<PuPatch>& patches);

// Fits points and unit normals in normalized coordinates (distinct, finite; near-coincident points merged by
// the caller). Patches are fitted in parallel on all hardware threads. Throws ink::Error naming the first patch
// whose system is singular or ill-conditioned.
PuHrbf fitPuHrbf(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                 const PuOptions& options = {}, PuStats* stats = nullptr, PhaseTimes* phases = nullptr);

// The float evaluation the device makes (pu_hrbf.glsl), vectorized over 4 nodes at a time: the CPU reference
// of the refinement and the measure of the fit as it will be drawn.
class PuFloat {
public:
    explicit PuFloat(const PuHrbf& model);
    float eval(const Eigen::Vector3f& x, Eigen::Vector3f& gradient) const;
    float evalHessian(const Eigen::Vector3f& x, Eigen::Vector3f& gradient, Eigen::Matrix3f& hessian) const;
    // eval at every point (as float), on all threads: (∇f, f) a point. The points are visited in the grid's cell
    // order, so that neighbours share the patches in cache (a scan's points come in any order: 3x faster at a
    // million points); each result depends on its point alone.
    std::vector<Eigen::Vector4f> evalMany(const std::vector<Eigen::Vector3d>& points) const;

private:
    float farField(const Eigen::Vector3f& x, Eigen::Vector3f& g, Eigen::Matrix3f* H) const;
    struct Patch {
        float cx, cy, cz, radius, ax, ay, az, b;
        uint32_t first, count;  // into the arrays, padded to a multiple of 4 with zero nodes
    };
    std::vector<Patch> patches_;
    std::vector<float> px_, py_, pz_, alpha_, bx_, by_, bz_;
    std::vector<float> coarse_;  // 8 floats a centre: p, α, β, 0
    float coarseA_[4] = {};      // a, b
    Eigen::Vector3f origin_;
    float invCell_ = 1, tau_ = 0;
    Eigen::Vector3i dims_;
    const std::vector<uint32_t>* cellStart_;
    const std::vector<uint32_t>* cellPatches_;
};

}  // namespace ink
