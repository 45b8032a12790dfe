// From a file to a fitted HRBF: load, normalize (unit diagonal), merge duplicates, choose control points by
// farthest-point sampling, fit (ALGORITHM.md §1–2).
#pragma once

#include "draw/camera.h"
#include "io/points.h"
#include "lines/feature_lines.h"
#include "surface/support.h"
#include "surface/surface.h"

#include <optional>
#include <string>

namespace ink {

// The global fit's control points when the input has more and none were asked for (the dense solve grows as m³).
constexpr size_t kDefaultControlPoints = 1000;
// The most points the partition of unity fits (about 10 s and 1 GiB on two cores at 10⁶).
constexpr size_t kMaxPuPoints = 2000000;

struct ModelOptions {
    // 0: every input point for the partition of unity, up to kDefaultControlPoints for the global fit.
    size_t controlPoints = 0;
    FitMethod method = FitMethod::PartitionOfUnity;
    double creaseAngleDeg = kCreaseAngleDeg;  // the feature lines' creases (feature_lines.h), in (0, 180)
    bool trim = true;            // drop what the input does not support (support.h): an open scan's extrapolated caps
    bool removeOutliers = true;  // a point cloud's points that stand alone, off its surface (clean.h)
    bool smoothNoise = true;     // a point cloud noisier than kNoisy moved onto its local quadrics (smoothScan)
    // Find a point cloud's crease lines (Model::features; a 10⁶-point scan's take 2 s): off where none will be
    // drawn. A mesh's crease and boundary lines, one pass over its edges, are always found.
    bool features = true;
    // Build what trims a drawing (the support, a point cloud's rims; with `trim`): off for a model that is only
    // saved (the .hrbf keeps neither; fit), 2.9 s of a 10⁶-point scan's fit. The fitted surface is the same.
    bool support = true;
};

struct Model {
    Surface surface;
    FitStats fit;  // at the control points, evaluated as the device evaluates (float for the partition of unity)
    PuStats patches;
    size_t inputPoints = 0;  // read from the file (a mesh's vertices)
    size_t faceSamples = 0;  // points sampled over a mesh's faces and fitted besides its vertices
    size_t mergedDuplicates = 0;
    size_t flippedNormals = 0;    // a point cloud's normals turned to agree with their neighbours' (orientNormals)
    size_t estimatedNormals = 0;  // a point cloud's points without a normal in the file, given one (estimateNormals)
    bool turnedOutward = false;   // every normal turned: they pointed inward (normalsPointInward)
    // A mesh cut flat at one end of its box (every open edge there, across one coordinate axis: a bust's neck, a
    // mushroom's stem, an open box's top): that axis is up, positive (openBase; the first picture's up axis before
    // the shape's, docs/usage.md). None for other models.
    std::optional<UpAxis> baseUp;
    size_t outliers = 0;  // a point cloud's points left out, standing alone off its surface (removeOutliers)
    // A point cloud's noise over its spacing (scanNoise; 0 for a mesh or a .hrbf model), and where it was smoothed
    // (over kNoisy, ModelOptions::smoothNoise) the median distance its points moved, normalized units.
    double noise = 0, smoothedBy = 0;
    double loadSeconds = 0;
    // The error at every point the fit was given (all input points, not only the control points), normalized
    // units (fractions of the diagonal), evaluated as the device evaluates.
    double inputMaxDistance = 0, inputMeanDistance = 0, inputMaxAngleDeg = 0;
    // A mesh's creases and boundaries, a point cloud's creases (none for .hrbf files), and where the input supports the
    // surface (everywhere without ModelOptions::trim, and for .hrbf files: they keep no input points).
    FeatureLines features;
    Support support;
    // The partition of unity's far field is trimmed too (with ModelOptions::trim, .hrbf models included): where
    // the patches' weights fade, away from the data, its coarse HRBF takes over, and its zero set there is a
    // stray sheet no input point stands for (a CAD part's flat faces grew domes 4% of the diagonal high).
    bool trimFarField = false;
    // Its back is drawn where it shows (GpuRefinement::twoSided): an open surface's inside, seen through its
    // openings. A mesh's where a part of it is open (meshParts: a rim, a hole, a fin); a point cloud's and a .hrbf
    // model's always, their rims unknown (on a closed surface the back shows almost nowhere: docs/usage.md, Open
    // surfaces).
    bool twoSided = true;

    // Whether the drawing keeps x (normalized coordinates): the input supports it, and where the partition of
    // unity is trimmed, its patches carry the blend (Σ w_i ≥ kFarFieldTrim · τ: the far field holds under a
    // fifth of it).
    bool holds(const Eigen::Vector3d& x) const;
    // Whether holds can be false anywhere (else the trimming has nothing to do).
    bool trims() const { return !support.empty() || trimFarField; }
};

// The drawing keeps a point whose patch weight S = Σ w_i is at least this share of τ: there the far field's
// weight τ (1 − S/τ)³ is at most τ/8, under a fifth of the blend. On the stipples of ten meshes (CGAL's and the
// bundled bunny), the points more than 1% of the diagonal off a mesh whose far field showed lie below it (joint,
// couplingdown, fandisk, armadillo all; cheese 2,188 of 2,243), and about 0.1% of the points on a mesh's surface
// or fewer (68 of 58,842 at the rims of the elephant's holes, where the patches thin out; docs/lines.md).
constexpr double kFarFieldTrim = 0.5;

// Strokes cut where the model does not hold them (Model::holds), as trimStrokes(strokes, support) does.
std::vector<PenStroke> trimStrokes(const std::vector<PenStroke>& strokes, const Model& model,
                                   size_t* dropped = nullptr);

// Refuses options no model can satisfy (--control-points above kMaxControlPoints for the global fit) before any
// work is done.
void checkModelOptions(const ModelOptions& options);

// Fits points given in the input's units. Throws ink::Error for too few distinct points or absurd requests.
Model fitModel(OrientedPoints points, const ModelOptions& options);
// Loads a mesh or point file and fits it, or loads a fitted model from a .hrbf file (options.controlPoints
// is then ignored; fit holds the stats at the stored centres, with seconds = 0). Every error from the file
// or the fit names `path`.
Model loadModel(const std::string& path, const ModelOptions& options);

}  // namespace ink
