#include "surface/model.h"

#include "base/common.h"
#include "base/point_tree.h"
#include "base/triangle.h"
#include "io/hrbf_io.h"
#include "io/normals.h"
#include "surface/clean.h"
#include "surface/surface_sampling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <unordered_map>

namespace ink {

namespace {

// Face samples the vertices' surface misses by more than this (normalized units: the diagonal is 1) are fitted
// too, in at most this many rounds after the vertices' own fit.
constexpr double kFaceSampleTolerance = 0.001;
constexpr int kFaceSampleRounds = 6;
// A mesh with fewer vertices is fitted to all its face samples at once.
constexpr size_t kFewVertices = 64;

// About the distance between neighbouring points, if they cover a surface as large as the faces of their
// bounding box: sqrt(box surface / 2 / count) (a closed surface fills about half of it); robust to how many points
// sit in close pairs (a crease's split vertices, face samples by vertices). A point cloud that fills little of its
// box (parts far apart, a scene) takes at most twice the median distance to the sixth nearest point, on up to 4,096
// of them (a cloud of three unit spheres 30 apart: 9,738 of its 12,000 points merged by the box's spacing, 5,272 so;
// closed shapes and scans measure 0.5 to 1.9 times that distance by their box, and stay as they were). Points
// nearer a probe than kNearCopy box spacings are not counted, as Support does not count them: a scan registered
// several times over puts clusters of near copies everywhere, which are what the merging is for.
double typicalSpacing(const std::vector<Eigen::Vector3d>& points, bool pointCloud) {
    if (points.size() < 2) return 0;
    Eigen::Vector3d lo = points.front(), hi = points.front();
    for (const auto& p : points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    Eigen::Vector3d d = hi - lo;
    double area = d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
    const double box = std::sqrt(area / double(points.size()));
    constexpr size_t kNearest = 64, kSixth = 6, kProbes = 4096;
    if (!pointCloud || points.size() < 2 * kNearest) return box;
    const PointCloud cloud{points};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    const double tooNear = kNearCopy * box;
    std::vector<double> sixth;
    const size_t stride = std::max<size_t>(1, points.size() / kProbes);
    std::array<uint32_t, kNearest> index{};
    std::array<double, kNearest> squared{};
    for (size_t i = 0; i < points.size(); i += stride) {
        const size_t found = tree.knnSearch(points[i].data(), kNearest, index.data(), squared.data());
        size_t counted = 0;
        for (size_t k = 0; k < found; ++k)
            if (squared[k] > tooNear * tooNear && ++counted == kSixth) {
                sixth.push_back(std::sqrt(squared[k]));
                break;
            }
    }
    if (sixth.size() * 2 < (points.size() + stride - 1) / stride) return box;  // most probes in clusters: keep the box
    std::nth_element(sixth.begin(), sixth.begin() + std::ptrdiff_t(sixth.size() / 2), sixth.end());
    return std::min(box, 2 * sixth[sixth.size() / 2]);
}

// The mesh with each position kept once (io/normals.h's weld: bit-identical coordinates): triangles renumbered,
// normals summed and normalized (each repeat's, area-weighted from its own side, adds up to the whole vertex's;
// repeats whose normals cancel keep the first one's, as the file gave it).
OrientedPoints weldByPosition(const OrientedPoints& mesh) {
    OrientedPoints out;
    const std::vector<uint32_t> renumber = io::weld(mesh.positions, out.positions);
    out.normals.assign(out.positions.size(), Eigen::Vector3d::Zero());
    for (size_t i = 0; i < mesh.positions.size(); ++i) out.normals[renumber[i]] += mesh.normals[i];
    std::vector<bool> set(out.normals.size(), false);
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const uint32_t k = renumber[i];
        if (set[k]) continue;
        set[k] = true;
        const double length = out.normals[k].norm();
        out.normals[k] = length > 1e-9 ? Eigen::Vector3d(out.normals[k] / length) : mesh.normals[i];
    }
    for (const Triangle& t : mesh.triangles) out.triangles.push_back({renumber[t[0]], renumber[t[1]], renumber[t[2]]});
    return out;
}

}  // namespace

void checkModelOptions(const ModelOptions& options) {
    if (options.method == FitMethod::Global && options.controlPoints > kMaxControlPoints)
        throw Error("--control-points " + std::to_string(options.controlPoints) +
                    " is more than the global fit can hold (at most " + std::to_string(kMaxControlPoints) +
                    ": the system needs (4m+4)² doubles); the default --fit pu takes any number");
    if (!(options.creaseAngleDeg > 0 && options.creaseAngleDeg < 180))
        throw Error("the crease angle (--crease-angle) must be in (0, 180) degrees");
    if (options.controlPoints > kMaxPuPoints)
        throw Error("--control-points " + std::to_string(options.controlPoints) +
                    " is more than the fit takes (at most " + std::to_string(kMaxPuPoints) + ")");
}

namespace {

// The error of the fitted surface at the given points (normalized), as the device evaluates it.
// `values`: the partition of unity's (∇f, f) at the points, in float.
void measureInputs(Model& model, const std::vector<Eigen::Vector3d>& points,
                   const std::vector<Eigen::Vector3d>& normals, const std::vector<Eigen::Vector4f>& values) {
    const Surface& s = model.surface;
    double sum = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        Eigen::Vector3d g;
        double f;
        if (!values.empty()) {
            f = values[i].w();
            g = values[i].head<3>().cast<double>();
        } else {
            f = s.eval(points[i], g);
        }
        double gn = g.norm(), distance = gn > 0 ? std::abs(f) / gn : INFINITY;
        model.inputMaxDistance = std::max(model.inputMaxDistance, distance);
        sum += distance;
        double angle = std::atan2(g.cross(normals[i]).norm(), g.dot(normals[i])) * 180.0 / M_PI;
        model.inputMaxAngleDeg = std::max(model.inputMaxAngleDeg, angle);
    }
    model.inputMeanDistance = points.empty() ? 0 : sum / double(points.size());
}

// Model::baseUp: where every open edge's vertex lies within kBasePlane of the mesh's extent across one coordinate axis,
// at that axis's one end (within kBasePlane of it), and spreads over at least kBaseWidth of the extent along both
// other axes, that axis is up, in its positive direction as every up axis the shape chooses: a base a scan was cut
// at lies at the low end (a bust's neck), and at the high end an opening is a container's (an open box, a bowl),
// whose opening is its top; a file is seldom stored upside down.
constexpr double kBasePlane = 0.05, kBaseWidth = 0.1;
std::optional<UpAxis> openBase(const std::vector<Eigen::Vector3d>& positions, const std::vector<bool>& rim) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo, rimLo = lo, rimHi = -lo;
    size_t rims = 0;
    for (size_t i = 0; i < positions.size(); ++i) {
        lo = lo.cwiseMin(positions[i]);
        hi = hi.cwiseMax(positions[i]);
        if (!rim[i]) continue;
        rimLo = rimLo.cwiseMin(positions[i]);
        rimHi = rimHi.cwiseMax(positions[i]);
        ++rims;
    }
    if (rims < 3) return std::nullopt;
    const Eigen::Vector3d extent = hi - lo;
    std::optional<UpAxis> up;
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        if (!(extent[a] > 0) || rimHi[a] - rimLo[a] > kBasePlane * extent[a] ||
            rimHi[b] - rimLo[b] < kBaseWidth * extent[b] || rimHi[c] - rimLo[c] < kBaseWidth * extent[c])
            continue;
        const bool low = rimLo[a] - lo[a] <= kBasePlane * extent[a], high = hi[a] - rimHi[a] <= kBasePlane * extent[a];
        if (low == high) continue;    // neither end, or a slab thinner than the band: no base
        if (up) return std::nullopt;  // two axes would do: no one base
        up = UpAxis(2 * a);
    }
    return up;
}

}  // namespace

Model fitModel(OrientedPoints points, const ModelOptions& options) {
    checkModelOptions(options);
    auto start = std::chrono::steady_clock::now();
    const bool global = options.method == FitMethod::Global;
    Model model;
    PhaseTimes& phases = model.fit.phases;
    model.inputPoints = points.positions.size();
    if (options.removeOutliers && (model.outliers = removeOutliers(points)))
        note("left out " + std::to_string(model.outliers) + " of the input's " + std::to_string(model.inputPoints) +
             " points that stand alone, off the surface their neighbours sample (outliers; --keep-outliers keeps "
             "them)");
    phases.lap("outliers");
    if (model.inputPoints > kMaxPuPoints && options.controlPoints == 0)
        throw Error("the input has " + std::to_string(model.inputPoints) + " points, more than the fit takes (" +
                    std::to_string(kMaxPuPoints) + "): choose fewer with --control-points");
    Frame frame = Frame::unitDiagonal(points.positions);
    // A point cloud's points without normals (an .xyz of positions alone, a PLY without nx ny nz, 0 0 0 in the file):
    // estimated from their neighbours below, then oriented with the rest (orientNormals). Duplicates merged first.
    const bool missing = points.triangles.empty() && std::any_of(points.normals.begin(), points.normals.end(),
                                                                 [](const Eigen::Vector3d& n) { return n.isZero(0); });
    if (missing) model.mergedDuplicates = mergeDuplicates(points, 1e-9 / frame.scale);
    OrientedPoints inputs;  // normalized, for the error at every input point
    for (size_t i = 0; i < points.positions.size(); ++i) {
        inputs.positions.push_back(frame.toNormalized(points.positions[i]));
        inputs.normals.push_back(points.normals[i]);
    }
    phases.lap("normalize");
    std::vector<char> estimated;
    if (missing) {
        model.estimatedNormals = estimateNormals(inputs.positions, inputs.normals, estimated);
        const size_t n = inputs.positions.size(), e = model.estimatedNormals;
        note("estimated the normals of " +
             (e == n ? "all " + std::to_string(n) + " points (the file gives none, or zero)"
                     : std::to_string(e) + " of " + std::to_string(n) + " points (the file gives them as zero)") +
             " from their " + std::to_string(kNormalNeighbours) + " nearest neighbours, oriented along the surface");
        phases.lap("normals");
    }
    if (points.triangles.empty()) {  // a mesh's winding orients its normals; a point cloud's may point every way
        model.flippedNormals = orientNormals(inputs.positions, inputs.normals, estimated);
        if (model.flippedNormals || model.estimatedNormals) points.normals = inputs.normals;
        if (model.flippedNormals) {
            note("turned " + std::to_string(model.flippedNormals) + " of the input's " +
                 std::to_string(points.normals.size()) +
                 " normals to agree with their neighbours' (they were not consistently oriented)");
        }
        // A noisy scan: the fit interpolates every point, and the noise became the surface's relief. Smoothed where
        // it is noisier than kNoisy (clean.h), each point among its neighbours on its own side (where the file gives
        // normals, oriented, they agree: a thin plate's two sides are not noise); normals estimated on the noise are
        // estimated again on the smoothed points, and oriented again.
        // Only the file's normals tell the sides: estimated on the noise, neighbours' disagree (zero: any side).
        std::vector<Eigen::Vector3d> sides = inputs.normals;
        for (size_t i = 0; i < estimated.size(); ++i)
            if (estimated[i]) sides[i].setZero();
        model.noise = scanNoise(inputs.positions, sides);
        if (options.smoothNoise && model.noise > kNoisy) {
            model.smoothedBy = smoothScan(inputs.positions, sides, smoothNeighbours(model.noise));
            inputs.normals = sides;
            if (model.estimatedNormals) {
                for (size_t i = 0; i < estimated.size(); ++i)
                    if (estimated[i]) inputs.normals[i].setZero();
                estimateNormals(inputs.positions, inputs.normals, estimated);
                orientNormals(inputs.positions, inputs.normals, estimated);
            }
            for (size_t i = 0; i < points.positions.size(); ++i) {
                points.positions[i] = frame.center + inputs.positions[i] / frame.scale;
                points.normals[i] = inputs.normals[i];
            }
            if (model.smoothedBy > 0) {  // not where a cloud has too few points to smooth
                char text[320];
                std::snprintf(
                    text, sizeof text,
                    "smoothed the points: their noise is %.2f of their spacing (over %.2f: a noisy scan); each "
                    "moved onto the quadric of its %zu nearest, by %.2g of the diagonal (median; --keep-noise "
                    "fits them as they are)",
                    model.noise, kNoisy, smoothNeighbours(model.noise), model.smoothedBy);
                note(text);
            }
        }
        phases.lap("noise");
    }
    // Inside out (a mesh wound so, a scan's normals estimated inward): turned outward, the winding with them. Drawn
    // as it was, its "front" was the inside of its far side (CGAL's head.off showed the inside of its face), its
    // contours' occlusion and its creases' facing tests turned round.
    if (normalsPointInward(inputs.positions, inputs.normals)) {
        model.turnedOutward = true;
        for (size_t i = 0; i < points.normals.size(); ++i) points.normals[i] = inputs.normals[i] = -inputs.normals[i];
        for (Triangle& t : points.triangles) std::swap(t[1], t[2]);
        note("turned the input's normals outward: its outermost points' normals pointed inward (inside out)");
    }
    phases.lap("orient");

    // A mesh's faces, sampled besides its vertices: the surface then follows the triangles, not only their
    // corners (a low-poly model's long thin triangles have no vertex along them).
    OrientedPoints samples;
    std::vector<bool> onRim;  // the sample lies on a triangle with an open edge
    OrientedPoints mesh;      // welded, normalized: its feature lines
    if (!points.triangles.empty()) {
        // Welded by position first: a file that repeats a vertex at a seam (for its texture or its normals) has
        // open edges there that are no rim, and corners whose neighbours the patches would not see (the Wuson's
        // 1,088 repeated vertices made every one of its 96,795 samples a rim sample).
        mesh = weldByPosition(points);
        std::vector<uint32_t> triangleOf;
        samples = sampleFaces(mesh, faceSampleCount(mesh), 1, &triangleOf, options.creaseAngleDeg);
        for (Eigen::Vector3d& x : mesh.positions) x = frame.toNormalized(x);
        std::unordered_map<uint64_t, uint32_t> edges;
        for (const Triangle& t : mesh.triangles)
            for (size_t e = 0; e < 3; ++e) ++edges[edgeKey(t[e], t[(e + 1) % 3])];
        // The vertices of open edges, and the samples of the triangles that touch one.
        std::vector<bool> rimVertex(mesh.positions.size(), false);
        for (const auto& [edge, uses] : edges)
            if (uses == 1) rimVertex[edge >> 32] = rimVertex[edge & 0xffffffffu] = true;
        model.baseUp = openBase(mesh.positions, rimVertex);
        onRim.resize(samples.positions.size());
        for (size_t i = 0; i < onRim.size(); ++i) {
            const Triangle& t = mesh.triangles[triangleOf[i]];
            onRim[i] = rimVertex[t[0]] || rimVertex[t[1]] || rimVertex[t[2]];
        }
        points.triangles.clear();
    }
    // The partition of unity of every point takes face samples only where its vertices alone leave the surface
    // off the mesh (adaptive, below). A face sample sits on the curved patch through the triangle's corners, which
    // agrees with the vertex normals only to first order: every sample fitted puts that disagreement into the
    // surface's curvature (the bunny with all its 16,939 samples, flat or on their patches: 17,000 to 66,000
    // contour cusps in the variants measured; with the 540 its vertices miss: 58).
    const bool adaptive = !global && options.controlPoints == 0 && !samples.positions.empty();
    if (!adaptive && !samples.positions.empty()) {
        model.faceSamples = samples.positions.size();
        note("sampled " + std::to_string(model.faceSamples) + " points over the mesh's faces, besides its " +
             std::to_string(points.positions.size()) + " vertices");
        points.positions.insert(points.positions.end(), samples.positions.begin(), samples.positions.end());
        points.normals.insert(points.normals.end(), samples.normals.begin(), samples.normals.end());
        samples = {};
    }

    phases.lap("mesh");
    // Duplicates make the system singular without a NaN to warn (ALGORITHM.md §2): merge them first.
    model.mergedDuplicates += mergeDuplicates(points, 1e-9 / frame.scale);
    if (model.mergedDuplicates)
        note("merged " + std::to_string(model.mergedDuplicates) + " duplicate point" +
             (model.mergedDuplicates == 1 ? "" : "s"));
    const size_t distinct = points.positions.size();
    if (distinct < 2)
        throw Error("too few distinct points to fit a surface: " + std::to_string(distinct) + " (need at least 2)");

    size_t wanted = options.controlPoints;
    if (wanted == 0) {
        wanted = global ? std::min(distinct, kDefaultControlPoints) : distinct;
        if (wanted < distinct)
            note("using " + std::to_string(wanted) + " of " + std::to_string(distinct) +
                 " points as control points of the global fit (--control-points to change, or --fit pu for all)");
    }
    if (wanted > distinct)
        note("asked for " + std::to_string(wanted) + " control points, but the model has " + std::to_string(distinct) +
             " distinct points: using all of them");
    wanted = std::min(wanted, distinct);

    // Farthest-point sampling in normalized coordinates: in the input's units the squared distances of a model
    // 1e-300 across underflow to zero, and every point would tie.
    for (Eigen::Vector3d& x : points.positions) x = frame.toNormalized(x);
    for (Eigen::Vector3d& x : samples.positions) x = frame.toNormalized(x);
    OrientedPoints chosen;
    if (wanted < distinct) {
        for (size_t i : farthestPointSample(points.positions, wanted)) {
            chosen.positions.push_back(points.positions[i]);
            chosen.normals.push_back(points.normals[i]);
        }
    } else {
        chosen = std::move(points);
    }

    phases.lap("choose");
    Surface& surface = model.surface;
    surface.method = options.method;
    surface.frame = frame;
    // Fits `fitted` (normalized) into `surface`, after merging its near points; `near` says what was merged.
    NearMerge near;
    auto fit = [&](OrientedPoints fitted) {
        // Control points within 1% of the typical spacing of another (a crease's split vertices, a seam) leave
        // the system too ill-conditioned to trust: merged, their normals averaged. The spacing is that of the
        // chosen points spread over about the surface of their box, robust to how many of them sit in such pairs.
        // The partition of unity merges within 25%: each patch's system is small, and a pair much closer than its
        // neighbours (a face sample beside a vertex) gives it coefficients large enough (Σ|α| ~ 10⁴) for float
        // evaluation to miss the surface: on the bunny with face samples, 2.6e-5 of the diagonal merging within
        // 1%, 1.9e-6 within 10%, 3.7e-7 within 25%. Points whose normals oppose merge within 1% only: farther apart
        // they are a thin part's two faces (a coin 1/100 as thick as wide lost every one within 25%).
        const double spacing = typicalSpacing(fitted.positions, mesh.positions.empty());
        near = mergeNearPoints(fitted, (global ? 0.01 : 0.25) * spacing, 0.01 * spacing);
        phases.lap("merge_near");
        if (fitted.positions.size() < 2)
            throw Error("too few distinct points to fit a surface: " + std::to_string(fitted.positions.size()) +
                        " (need at least 2)");
        if (global) {
            try {
                Progress progress("fit", 1);
                surface.global = fitHrbf(fitted.positions, fitted.normals, &model.fit);
                phases.lap("solve");
            } catch (const Error& e) {
                // The one change that helps: farthest-point sampling keeps fewer points farther apart.
                const size_t fewer = std::max<size_t>(4, fitted.positions.size() / 2);
                if (std::string(e.what()).find("ill-conditioned") == std::string::npos &&
                    std::string(e.what()).find("singular") == std::string::npos)
                    throw;
                throw Error(std::string(e.what()) + "; fit fewer control points (--control-points " +
                            std::to_string(fewer) + ")");
            }
        } else {
            surface.pu = fitPuHrbf(fitted.positions, fitted.normals, {}, &model.patches, &phases);
            model.fit.relativeResidual = model.patches.maxRelativeResidual;
        }
        return fitted;
    };

    // The partition of unity of every point fits a mesh's vertices first, then, in rounds, the face samples its
    // surface misses by more than kFaceSampleTolerance of the diagonal (a thin part between distant vertices, a
    // long flat triangle), or its patches do not carry (the far field's, trimmed), until it misses none. A mesh of a
    // few vertices takes all its samples at once.
    std::string sampled;
    if (adaptive && chosen.positions.size() >= kFewVertices) {
        // An open rim is where the fit extrapolates: sampled densely, its patches are small and the surface stops
        // close to it (an open hemisphere: 98.1% of the refined points within 1% of the mesh with its vertices
        // alone, 99.x% with its rim's samples).
        std::vector<bool> used = onRim;
        const size_t vertices = chosen.positions.size();
        for (size_t i = 0; i < samples.positions.size(); ++i)
            if (used[i]) {
                chosen.positions.push_back(samples.positions[i]);
                chosen.normals.push_back(samples.normals[i]);
                ++model.faceSamples;
            }
        for (int round = 0;; ++round) {
            OrientedPoints fitted = fit(chosen);
            size_t added = 0;
            for (size_t i = 0; i < samples.positions.size() && round < kFaceSampleRounds; ++i) {
                if (used[i]) continue;
                Eigen::Vector3d g;
                const double f = surface.eval(samples.positions[i], g), gn = g.norm();
                // Followed, and by the patches: where their weights fade between the sparse vertices of large
                // faces the far field draws the surface, and the drawing drops it there (Model::holds).
                const bool covered = global || !options.trim ||
                                     surface.pu.patchWeight(samples.positions[i]) >= kFarFieldTrim * surface.pu.tau;
                if (gn > 0 && std::abs(f) / gn <= kFaceSampleTolerance && g.dot(samples.normals[i]) > 0 && covered)
                    continue;
                used[i] = true;
                chosen.positions.push_back(samples.positions[i]);
                chosen.normals.push_back(samples.normals[i]);
                ++added;
            }
            model.faceSamples += added;
            phases.lap("face_samples");
            if (added == 0) {
                chosen = std::move(fitted);
                break;
            }
        }
        sampled = "fitted " + std::to_string(model.faceSamples) + " of " + std::to_string(samples.positions.size()) +
                  " face samples besides the mesh's " + std::to_string(vertices) +
                  " vertices: those its vertices alone missed by more than 0.1% of the diagonal";
    } else {
        if (adaptive) {
            model.faceSamples = samples.positions.size();
            sampled = "sampled " + std::to_string(model.faceSamples) + " points over the mesh's faces, besides its " +
                      std::to_string(chosen.positions.size()) + " vertices";
            chosen.positions.insert(chosen.positions.end(), samples.positions.begin(), samples.positions.end());
            chosen.normals.insert(chosen.normals.end(), samples.normals.begin(), samples.normals.end());
        }
        chosen = fit(std::move(chosen));
    }
    if (near.merged)
        note("merged " + std::to_string(near.merged) + " control point" + (near.merged == 1 ? "" : "s") + " within " +
             (global ? "1%" : "25%") +
             " of the point spacing of another (creases, seams, face samples by vertices), their normals averaged");
    if (near.dropped)
        note("dropped " + std::to_string(near.dropped) + " control point" + (near.dropped == 1 ? "" : "s") +
             " in clusters whose normals cancel (both sides of a thin sheet at one place)");
    if (!sampled.empty()) note(sampled);
    surface.centers = std::move(chosen.positions);
    surface.normals = std::move(chosen.normals);
    if (!global) model.patches.seams = measureSeams(surface.pu);
    phases.lap("seams");
    chooseSeeds(surface);
    if (adaptive) {
        // Seeds from the vertices and every face sample, projected onto F = 0: a big flat face with few vertices
        // is seeded as densely as the rest.
        std::vector<Eigen::Vector3d> candidates = surface.centers, facing = surface.normals;
        for (size_t j = 0; j < samples.positions.size(); ++j) {
            Eigen::Vector3d x = samples.positions[j];
            bool on = false;
            const Eigen::Vector3d start = x;
            for (int k = 0; k < 6 && !on; ++k) {
                Eigen::Vector3d g;
                const double f = surface.eval(x, g), g2 = g.squaredNorm();
                if (!(g2 > 0) || !std::isfinite(f)) break;
                x -= (f / g2) * g;
                on = std::abs(f) < 1e-9 * std::sqrt(g2);
            }
            if (on && (x - start).norm() < 0.01) candidates.push_back(x), facing.push_back(samples.normals[j]);
        }
        surface.seeds.clear();
        for (size_t i : farthestPointSample(candidates, std::min(candidates.size(), kMaxSeeds), &facing))
            surface.seeds.push_back(candidates[i]);
    }
    phases.lap("seeds");
    // The partition of unity in float, as the device draws it, at the centres and at the inputs: the same points
    // for a point cloud nothing was merged in (a scan), evaluated once then.
    std::vector<Eigen::Vector4f> atCentres, atInputs;
    if (!global) {
        const PuFloat floatModel(surface.pu);
        atCentres = floatModel.evalMany(surface.centers);
        if (inputs.positions != surface.centers) atInputs = floatModel.evalMany(inputs.positions);
    }
    FitStats measured = global ? measureFit(surface) : measureFit(surface, atCentres);
    model.fit.controlPoints = measured.controlPoints;
    model.fit.maxDistance = measured.maxDistance;
    model.fit.maxNormalAngleDeg = measured.maxNormalAngleDeg;
    phases.lap("measure");
    measureInputs(model, inputs.positions, inputs.normals, global || !atInputs.empty() ? atInputs : atCentres);
    phases.lap("measure_inputs");
    // A mesh's lines always (one pass over its edges: 7 ms for CGAL's elk.off); a point cloud's creases where asked.
    if (!mesh.triangles.empty())
        model.features = meshFeatures(mesh, surface, {options.creaseAngleDeg});
    else if (options.features)
        model.features = pointFeatures(inputs, surface, {options.creaseAngleDeg});
    if (!mesh.triangles.empty()) model.twoSided = meshParts(mesh).anyOpen;
    phases.lap("features");
    // A mesh supports the surface near its triangles, by twice what the fit misses its vertices by where that is
    // more (a fit of fewer control points); points near themselves.
    if (options.trim && !mesh.triangles.empty() && 2 * model.inputMaxDistance > kMaxMeshSupport) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "not trimmed to the mesh (its far field still is): the fit misses the mesh's vertices by up to "
                      "%.1f%% of the diagonal (more control points follow it closer)",
                      100 * model.inputMaxDistance);
        note(text);
    } else if (options.trim && options.support) {
        model.support = mesh.triangles.empty() ? Support(inputs.positions, inputs.normals)
                                               : Support(mesh, 2 * model.inputMaxDistance);
    }
    model.trimFarField = options.trim && !global;
    if (options.trim && options.support) phases.lap("support");
    // A point cloud's open rims, as a mesh's edges of one face: drawn as its boundaries, and the support ends there.
    if (options.trim && mesh.triangles.empty() && !model.support.empty()) {
        const std::vector<Eigen::Vector3f> outward =
            cloudRims(inputs, surface, model.support, [&](const Eigen::Vector3d& x) { return model.holds(x); });
        std::vector<Support::RimSample> samples, kept;
        const std::vector<PenStroke> lines =
            rimLines(inputs, outward, surface, model.support, {options.creaseAngleDeg}, &samples);
        // A rim has no input beyond it: a line with input points past a third of its samples (a chain across data,
        // along a closed scan's rough edge: cube.pwn's 23 lines became 20) is no rim; the rest cut the support where
        // no input lies beyond them.
        size_t at = 0;
        for (const PenStroke& line : lines) {
            std::vector<bool> clear(line.points.size());
            size_t beyond = 0;
            for (size_t k = 0; k < clear.size(); ++k) {
                clear[k] = !model.support.inputBeyond(samples[at + k]);
                beyond += clear[k] ? 0 : 1;
            }
            if (3 * beyond <= clear.size()) {
                model.features.boundaries.push_back(line);
                for (size_t k = 0; k < clear.size(); ++k)
                    if (clear[k]) kept.push_back(samples[at + k]);
            }
            at += clear.size();
        }
        model.support.setRims(std::move(kept));
        phases.lap("rims");
    }
    model.fit.seconds = secondsSince(start);
    return model;
}

namespace {

bool isHrbfFile(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".hrbf";
}

}  // namespace

bool Model::holds(const Eigen::Vector3d& x) const {
    if (trimFarField && !(surface.pu.patchWeight(x) >= kFarFieldTrim * surface.pu.tau)) return false;
    return support.supports(x);
}

std::vector<PenStroke> trimStrokes(const std::vector<PenStroke>& strokes, const Model& model, size_t* dropped) {
    if (!model.trims()) return strokes;
    return keepRuns(
        strokes, [&](size_t s, size_t i) { return model.holds(strokes[s].points[i].cast<double>()); }, dropped);
}

Model loadModel(const std::string& path, const ModelOptions& options) {
    checkModelOptions(options);
    auto start = std::chrono::steady_clock::now();
    if (isHrbfFile(path)) {
        Model model;
        FitStats measured;                          // the reader evaluates the model at its centres anyway
        model.surface = loadHrbf(path, &measured);  // first: a broken file gets one line, not a note and the error
        if (options.controlPoints)
            note("--control-points is ignored for '" + path + "': a .hrbf model is already fitted");
        model.inputPoints = model.surface.size();
        model.loadSeconds = secondsSince(start);
        model.fit = measured;  // measureFit's figures; relativeResidual and seconds stay 0: nothing was solved
        // It keeps no input to trim by, but its far field is the model's own.
        model.trimFarField = options.trim && model.surface.method == FitMethod::PartitionOfUnity;
        if (model.surface.method == FitMethod::PartitionOfUnity) {  // the inputs are the centres: measured already
            model.inputMaxDistance = measured.maxDistance;
            model.inputMaxAngleDeg = measured.maxNormalAngleDeg;
            model.inputMeanDistance = measured.meanDistance;
        } else {
            measureInputs(model, model.surface.centers, model.surface.normals, {});  // the global fit: in double
        }
        return model;
    }
    OrientedPoints points = loadPoints(path);
    double load = secondsSince(start);
    Model model;
    try {
        model = fitModel(std::move(points), options);
    } catch (const Error& e) {
        // The loaders' messages start with the path; the fit's ("too few distinct points") say which file.
        throw Error(path + ": " + e.what());
    }
    model.loadSeconds = load;
    return model;
}

}  // namespace ink
