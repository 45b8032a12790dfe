#include "model.h"

#include "common.h"
#include "hrbf_io.h"
#include "surface_sampling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>

namespace ink {

namespace {

// About the distance between neighbouring points, if they cover a surface as large as the faces of their
// bounding box: sqrt(box surface / 2 / count) (a closed surface fills about half of it).
double typicalSpacing(const std::vector<Eigen::Vector3d>& points) {
    if (points.size() < 2) return 0;
    Eigen::Vector3d lo = points.front(), hi = points.front();
    for (const auto& p : points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    Eigen::Vector3d d = hi - lo;
    double area = d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
    return std::sqrt(area / double(points.size()));
}

}  // namespace

void checkModelOptions(const ModelOptions& options) {
    if (options.method == FitMethod::Global && options.controlPoints > kMaxControlPoints)
        throw Error("--control-points " + std::to_string(options.controlPoints) +
                    " is more than the global fit can hold (at most " + std::to_string(kMaxControlPoints) +
                    ": the system needs (4m+4)² doubles); the default --fit pu takes any number");
    if (options.controlPoints > kMaxPuPoints)
        throw Error("--control-points " + std::to_string(options.controlPoints) +
                    " is more than the fit takes (at most " + std::to_string(kMaxPuPoints) + ")");
}

namespace {

// The error of the fitted surface at the given points (normalized), as the device evaluates it.
void measureInputs(Model& model, const std::vector<Eigen::Vector3d>& points,
                   const std::vector<Eigen::Vector3d>& normals) {
    const Surface& s = model.surface;
    std::unique_ptr<PuFloat> pu;
    if (s.method == FitMethod::PartitionOfUnity) pu = std::make_unique<PuFloat>(s.pu);
    double sum = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        Eigen::Vector3d g;
        double f;
        if (pu) {
            Eigen::Vector3f gf;
            f = pu->eval(points[i].cast<float>(), gf);
            g = gf.cast<double>();
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

}  // namespace

Model fitModel(OrientedPoints points, const ModelOptions& options) {
    checkModelOptions(options);
    auto start = std::chrono::steady_clock::now();
    const bool global = options.method == FitMethod::Global;
    Model model;
    model.inputPoints = points.positions.size();
    if (model.inputPoints > kMaxPuPoints && options.controlPoints == 0)
        throw Error("the input has " + std::to_string(model.inputPoints) + " points, more than the fit takes (" +
                    std::to_string(kMaxPuPoints) + "): choose fewer with --control-points");
    Frame frame = Frame::unitDiagonal(points.positions);
    OrientedPoints inputs;  // normalized, for the error at every input point
    for (size_t i = 0; i < points.positions.size(); ++i) {
        inputs.positions.push_back(frame.toNormalized(points.positions[i]));
        inputs.normals.push_back(points.normals[i]);
    }

    // A mesh's faces, sampled besides its vertices: the surface then follows the triangles, not only their
    // corners (a low-poly model's long thin triangles have no vertex along them).
    if (!points.triangles.empty()) {
        size_t count = faceSampleCount(points);
        OrientedPoints samples = sampleFaces(points, count, 1);
        model.faceSamples = samples.positions.size();
        if (model.faceSamples)
            note("sampled " + std::to_string(model.faceSamples) + " points over the mesh's " +
                 std::to_string(points.triangles.size()) + " triangles, besides its " +
                 std::to_string(points.positions.size()) + " vertices");
        points.positions.insert(points.positions.end(), samples.positions.begin(), samples.positions.end());
        points.normals.insert(points.normals.end(), samples.normals.begin(), samples.normals.end());
        points.triangles.clear();
    }

    // Duplicates make the system singular without a NaN to warn (ALGORITHM.md §2): merge them first.
    model.mergedDuplicates = mergeDuplicates(points, 1e-9 / frame.scale);
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
    OrientedPoints chosen;
    if (wanted < distinct) {
        for (size_t i : farthestPointSample(points.positions, wanted)) {
            chosen.positions.push_back(points.positions[i]);
            chosen.normals.push_back(points.normals[i]);
        }
    } else {
        chosen = std::move(points);
    }
    // Control points within 1% of the typical spacing of another (a crease's split vertices, a seam) leave the
    // system too ill-conditioned to trust: merged, their normals averaged. The spacing is that of the chosen
    // points spread over about the surface of their box, robust to how many of them sit in such pairs.
    // The partition of unity merges within 25%: each patch's system is small, and a pair much closer than its
    // neighbours (a face sample beside a vertex) gives it coefficients large enough (Σ|α| ~ 10⁴) for float
    // evaluation to miss the surface: on the bunny with face samples, 2.6e-5 of the diagonal merging within 1%,
    // 1.9e-6 within 10%, 3.7e-7 within 25%.
    const double tolerance = (global ? 0.01 : 0.25) * typicalSpacing(chosen.positions);
    NearMerge near = mergeNearPoints(chosen, tolerance);
    if (near.merged)
        note("merged " + std::to_string(near.merged) + " control point" + (near.merged == 1 ? "" : "s") + " within " +
             (global ? "1%" : "25%") +
             " of the point spacing of another (creases, seams, face samples by vertices), their normals averaged");
    if (near.dropped)
        note("dropped " + std::to_string(near.dropped) + " control point" + (near.dropped == 1 ? "" : "s") +
             " in clusters whose normals cancel (both sides of a thin sheet at one place)");
    if (chosen.positions.size() < 2)
        throw Error("too few distinct points to fit a surface: " + std::to_string(chosen.positions.size()) +
                    " (need at least 2)");

    Surface& surface = model.surface;
    surface.method = options.method;
    surface.frame = frame;
    if (global) {
        try {
            Progress progress("fit", 1);
            surface.global = fitHrbf(chosen.positions, chosen.normals, &model.fit);
        } catch (const Error& e) {
            // The one change that helps: farthest-point sampling keeps fewer points farther apart.
            const size_t fewer = std::max<size_t>(4, chosen.positions.size() / 2);
            if (std::string(e.what()).find("ill-conditioned") == std::string::npos &&
                std::string(e.what()).find("singular") == std::string::npos)
                throw;
            throw Error(std::string(e.what()) + "; fit fewer control points (--control-points " +
                        std::to_string(fewer) + ")");
        }
    } else {
        surface.pu = fitPuHrbf(chosen.positions, chosen.normals, {}, &model.patches);
        model.fit.relativeResidual = model.patches.maxRelativeResidual;
    }
    surface.centers = std::move(chosen.positions);
    surface.normals = std::move(chosen.normals);
    chooseSeeds(surface);
    FitStats measured = measureFit(surface);
    model.fit.controlPoints = measured.controlPoints;
    model.fit.maxDistance = measured.maxDistance;
    model.fit.maxNormalAngleDeg = measured.maxNormalAngleDeg;
    measureInputs(model, inputs.positions, inputs.normals);
    model.fit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return model;
}

namespace {

bool isHrbfFile(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".hrbf";
}

}  // namespace

Model loadModel(const std::string& path, const ModelOptions& options) {
    checkModelOptions(options);
    auto start = std::chrono::steady_clock::now();
    if (isHrbfFile(path)) {
        Model model;
        model.surface = loadHrbf(path);  // first: a broken file gets one line, not a note and then the error
        if (options.controlPoints)
            note("--control-points is ignored for '" + path + "': a .hrbf model is already fitted");
        model.inputPoints = model.surface.size();
        model.loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        model.fit = measureFit(model.surface);  // relativeResidual and seconds stay 0: nothing was solved
        measureInputs(model, model.surface.centers, model.surface.normals);
        return model;
    }
    OrientedPoints points = loadPoints(path);
    double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
