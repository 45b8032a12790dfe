// A 4-symmetric direction field (a cross field) on points of the HRBF surface, for hatching (hatching.h,
// docs/lines.md): the principal curvature directions of the fit where the surface is clearly anisotropic, smoothly
// interpolated through umbilic and flat regions. Solved on the device (cross_field_device.h) or on the CPU, its twin,
// in parallel, with the same result for any number of threads; the graph both solve on, the comb and the look-up
// are the host's. No Vulkan here.
//
// Each point holds one unit tangent d; the cross is {±d, ±n × d}. Seeds: the direction of the largest principal
// curvature, from the shape operator of the fit's analytic Hessian (S = P H P / |∇f|), with a confidence
// c = a² / (1 + a²), a = |k1 − k2| · featureSize (0 on a sphere or a plane, → 1 where one curvature dominates).
// Smoothing as Instant Meshes does on point clouds (Jakob et al. 2015), over the k nearest neighbours on a
// hierarchy of point subsets, coarse to fine, but averaging crosses as the complex numbers e^{4iθ} in each point's
// tangent frame (Knöppel et al. 2013; Ray et al. 2008), which needs no matching of the four directions:
//   z_i ← Σ_j e^{4iθ_j} + fidelity · c_i · e^{4iψ_i},   θ_i ← arg(z_i) / 4,
// θ_j a neighbour's direction projected into i's tangent plane, ψ_i the seed's. Jacobi sweeps (each reads the
// previous sweep only): the result does not depend on the thread schedule.
#pragma once

#include "lines/lines.h"
#include "surface/surface.h"

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ink {

struct CrossFieldOptions {
    uint32_t neighbours = 10;                     // k of the k-nearest-neighbour graph on every level
    uint32_t coarseSweeps = 60, fineSweeps = 12;  // on the coarsest level, and on each finer one
    // The length against which |k1 − k2| is judged (normalized units, the diagonal is 1): a cylinder of this radius
    // gets confidence 1/2. Smaller trusts only sharper bends.
    double featureSize = 0.12;
    // Weight of a point's own curvature seed at confidence 1, against the weight 1 of each neighbour: larger
    // follows the curvature more closely and smooths its noise less.
    double fidelity = 8.0;
    unsigned threads = 0;  // 0: all hardware threads
};

// The points the field is smoothed on: the samples (level 0), then coarser subsets, each level's points one
// stand-in per cell of a grid twice as coarse as the last (each side of a thin part its own), stored one level
// after another. Built on the host from the samples' positions and normals; the CPU solve and the device's
// (cross_field_device.h) both run on it, so that they differ only by their arithmetic.
struct CrossFieldGraph {
    uint32_t k = 0;                    // neighbours a point
    std::vector<uint32_t> levelStart;  // level l is [levelStart[l], levelStart[l + 1]); level 0 the samples
    std::vector<uint32_t> neighbours;  // k a point: the nearest on the same side of the surface (kNone where fewer)
    std::vector<uint32_t> parent;      // its stand-in on the next coarser level (kNone on the coarsest)
    // The points a coarse point stands for: children[childStart[i], childStart[i + 1]), the first of them the one
    // whose position and normal it has (none for the samples).
    std::vector<uint32_t> childStart, children;
    double spacing = 0;  // the samples' median distance to their nearest neighbour
    static constexpr uint32_t kNone = UINT32_MAX;

    size_t levels() const { return levelStart.empty() ? 0 : levelStart.size() - 1; }
    uint32_t points() const { return levelStart.empty() ? 0 : levelStart.back(); }
};
CrossFieldGraph buildCrossFieldGraph(const std::vector<SurfaceSample>& samples, uint32_t k, unsigned threads = 0);

// The field solved on a graph, at the samples: the unit normal (the fit's ∇f, its sign the sample's), the seed (the
// direction of the largest |k|) and its confidence, and one of the four directions of the smoothed cross.
struct CrossFieldSolution {
    std::vector<Eigen::Vector3d> normals, principal, directions;
    std::vector<float> confidence;
};
// On the CPU, in double, in parallel (the same result for any number of threads).
CrossFieldSolution solveCrossField(const Surface& surface, const std::vector<SurfaceSample>& samples,
                                   const CrossFieldGraph& graph, const CrossFieldOptions& options = {});

class CrossField {
public:
    CrossField() = default;
    // The graph built and the field solved on the CPU.
    CrossField(const Surface& surface, const std::vector<SurfaceSample>& samples,
               const CrossFieldOptions& options = {});
    // From a solution on `graph` (either solve's): the comb and the look-up grid; `featureSize` as the solve's.
    CrossField(const std::vector<SurfaceSample>& samples, const CrossFieldGraph& graph, CrossFieldSolution solution,
               double featureSize = CrossFieldOptions{}.featureSize);

    size_t size() const { return positions_.size(); }
    const std::vector<Eigen::Vector3d>& positions() const { return positions_; }
    const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
    const std::vector<Eigen::Vector3d>& directions() const { return directions_; }  // one of each point's four
    const std::vector<Eigen::Vector3d>& principal() const { return principal_; }    // largest |k|, the seed
    // One of each point's four directions chosen consistently over the surface (a comb): where the curvature is
    // clear (confidence ≥ kAnchorConfidence), the one nearest the point's own smaller principal curvature; elsewhere
    // grown from those over the neighbour graph, most confident first, each point matched to the one it was reached
    // from. The choices disagree only across a few cuts, in the least anisotropic regions (a 4-symmetric field with
    // singularities cannot be combed everywhere).
    static constexpr float kAnchorConfidence = 0.5f;  // |k1 − k2| · featureSize ≥ 1
    const std::vector<Eigen::Vector3d>& combed() const { return combed_; }
    // Flat ground: points whose normal turns by less than kFlatBend · |Δx| / featureSize to any neighbour's (a
    // plane, or a bend wider than 20 feature sizes). Each piece of it is given one direction, field and comb: the
    // way the curved points around it are combed where they agree on one (|Σ e^{2iθ}| ≥ kFramed a point), else
    // the tangent of a fixed axis (the model's y, its x where the normal is near ±y). Grown from the curved parts
    // around it, a flat face framed by fillets was split along its diagonals; following the smoothed field, its
    // strokes bent with it.
    static constexpr double kFlatBend = 0.05, kFramed = 0.25;
    const std::vector<char>& flat() const { return flat_; }
    const std::vector<float>& confidence() const { return confidence_; }
    double radius() const { return radius_; }  // of an interpolation (lookup)

    // The field at x (unit normal n) as the one of its four directions nearest `reference` (a tangent): the
    // neighbours' crosses within radius() averaged as e^{4iθ} in x's tangent plane. `coherence` (0..1): |Σ w z| / Σ w,
    // near 0 beside a singularity where the neighbours' crosses cancel. False without neighbours.
    // `flatComb`, when given: the combed directions c of the neighbours on flat ground (flat()) as seen from the
    // reference, Σ w e^{2iφ} over them / Σ w over all, φ the angle from the reference to c: (1, 0) where all are
    // flat and the reference runs along their comb, (−1, 0) across it, 0 away from flat ground.
    bool lookup(const Eigen::Vector3d& x, const Eigen::Vector3d& n, const Eigen::Vector3d& reference,
                Eigen::Vector3d& direction, double* coherence = nullptr, Eigen::Vector2d* flatComb = nullptr) const;

    // Of the cross {±d, ±n × d}, the direction nearest `reference`; false when reference ∥ n.
    static bool nearestOf(const Eigen::Vector3d& d, const Eigen::Vector3d& n, const Eigen::Vector3d& reference,
                          Eigen::Vector3d& out);

private:
    std::vector<Eigen::Vector3d> positions_, normals_, directions_, principal_, combed_;
    std::vector<float> confidence_;
    std::vector<char> flat_;
    double radius_ = 0;
    double inverseCell_ = 0;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// The direction of u in the tangent frame (t1, t2) raised to the fourth power: e^{4iθ} as (cos 4θ, sin 4θ) times
// |u|⁴ / |u|⁴ (unit). Zero for u ⟂ the plane.
Eigen::Vector2d fourthPower(const Eigen::Vector3d& u, const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);

}  // namespace ink
