// Fidelity of points to a mesh (fidelity.h): a k-d tree of the points for coverage, a grid of the triangles
// for accuracy.
#include "surface/fidelity.h"
#include "base/point_tree.h"

#include "base/common.h"
#include "base/triangle.h"
#include "surface/surface_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>

namespace ink {

using Eigen::Vector3d;

namespace {

// Runs body(begin, end) over [0, n) in one chunk per hardware thread.
template <class Body>
void parallelChunks(size_t n, Body body) {
    size_t threads = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, 64);
    threads = std::min(threads, std::max<size_t>(1, n / 1024));
    std::vector<std::thread> pool;
    for (size_t k = 1; k < threads; ++k) pool.emplace_back(body, n * k / threads, n * (k + 1) / threads);
    body(size_t(0), n / threads);
    for (std::thread& t : pool) t.join();
}

// The triangles with area, bucketed in a uniform grid: each in every cell whose centre lies within half a cell
// diagonal of it (every cell it touches, and a few it nearly does).
class TriangleGrid {
public:
    explicit TriangleGrid(const OrientedPoints& mesh) : mesh_(mesh) {
        std::vector<double> areas = triangleAreas(mesh);
        for (size_t t = 0; t < areas.size(); ++t)
            if (areas[t] > 0) triangles_.push_back(mesh.triangles[t]);
        if (triangles_.empty()) return;
        lo_ = hi_ = mesh.positions[triangles_[0][0]];
        for (const Triangle& t : triangles_)
            for (uint32_t i : t) {
                lo_ = lo_.cwiseMin(mesh.positions[i]);
                hi_ = hi_.cwiseMax(mesh.positions[i]);
            }
        // About two cells a triangle, between 16³ and 128³ cells; no thinner than 1/1024 of the diagonal, so that a
        // flat mesh's box still has a volume to divide.
        Vector3d extent = hi_ - lo_;
        const double diagonal = extent.norm();
        const double cells = std::clamp(2.0 * double(triangles_.size()), 4096.0, 2097152.0);
        extent = extent.cwiseMax(diagonal / 1024);
        cell_ = std::max(std::cbrt(extent.prod() / cells), diagonal / 1024);
        for (int a = 0; a < 3; ++a) dims_[a] = std::max<int64_t>(1, int64_t(std::ceil((hi_[a] - lo_[a]) / cell_)));
        const double reach = cell_ * std::sqrt(3.0) / 2;
        std::vector<std::pair<uint32_t, uint32_t>> pairs;  // cell, triangle
        for (size_t t = 0; t < triangles_.size(); ++t) {
            const Vector3d &a = corner(t, 0), &b = corner(t, 1), &c = corner(t, 2);
            std::array<int64_t, 3> from = cellOf(a.cwiseMin(b).cwiseMin(c)), to = cellOf(a.cwiseMax(b).cwiseMax(c));
            for (int64_t z = from[2]; z <= to[2]; ++z)
                for (int64_t y = from[1]; y <= to[1]; ++y)
                    for (int64_t x = from[0]; x <= to[0]; ++x) {
                        Vector3d centre = lo_ + cell_ * Vector3d(double(x) + 0.5, double(y) + 0.5, double(z) + 0.5);
                        if ((closestPointOnTriangle(centre, a, b, c) - centre).norm() <= reach)
                            pairs.emplace_back(uint32_t(index(x, y, z)), uint32_t(t));
                    }
        }
        std::sort(pairs.begin(), pairs.end());
        start_.assign(size_t(dims_[0] * dims_[1] * dims_[2]) + 1, 0);
        for (const auto& p : pairs) ++start_[p.first + 1];
        for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
        items_.reserve(pairs.size());
        for (const auto& p : pairs) items_.push_back(p.second);
    }

    bool empty() const { return triangles_.empty(); }

    // The distance from p to the nearest triangle. `seen` (one per thread, as many as the triangles) marks
    // the triangles measured for this query with `stamp`.
    double distance(const Vector3d& p, std::vector<uint32_t>& seen, uint32_t stamp) const {
        // Outside the grid, the search starts from p's projection q onto it: for any y in the box,
        // |p − y| ≥ |q − y|, so the rings' bounds still hold.
        const Vector3d q = p.cwiseMax(lo_).cwiseMin(hi_);
        const std::array<int64_t, 3> c = cellOf(q);
        double best = INFINITY;
        const int64_t rings = std::max({dims_[0], dims_[1], dims_[2]});
        for (int64_t r = 0; r <= rings; ++r) {
            // Cells at Chebyshev distance r from c.
            for (int64_t z = c[2] - r; z <= c[2] + r; ++z) {
                if (z < 0 || z >= dims_[2]) continue;
                for (int64_t y = c[1] - r; y <= c[1] + r; ++y) {
                    if (y < 0 || y >= dims_[1]) continue;
                    const bool face = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
                    for (int64_t x = c[0] - r; x <= c[0] + r; x += face ? 1 : std::max<int64_t>(1, 2 * r)) {
                        if (x < 0 || x >= dims_[0]) continue;
                        const size_t cell = index(x, y, z);
                        for (uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
                            uint32_t t = items_[k];
                            if (seen[t] == stamp) continue;
                            seen[t] = stamp;
                            best = std::min(
                                best, (closestPointOnTriangle(p, corner(t, 0), corner(t, 1), corner(t, 2)) - p).norm());
                        }
                    }
                }
            }
            // Every cell not searched yet is at least r cells from q's: at least r · cell away from it.
            if (best <= double(r) * cell_) break;
        }
        return best;
    }

    size_t triangles() const { return triangles_.size(); }

private:
    const Vector3d& corner(size_t t, int k) const { return mesh_.positions[triangles_[t][size_t(k)]]; }
    std::array<int64_t, 3> cellOf(const Vector3d& p) const {
        std::array<int64_t, 3> c;
        for (int a = 0; a < 3; ++a)
            c[size_t(a)] = std::clamp<int64_t>(int64_t(std::floor((p[a] - lo_[a]) / cell_)), 0, dims_[a] - 1);
        return c;
    }
    size_t index(int64_t x, int64_t y, int64_t z) const { return size_t((z * dims_[1] + y) * dims_[0] + x); }

    const OrientedPoints& mesh_;
    std::vector<Triangle> triangles_;
    Vector3d lo_ = Vector3d::Zero(), hi_ = Vector3d::Zero();
    double cell_ = 1;
    std::array<int64_t, 3> dims_{1, 1, 1};
    std::vector<uint32_t> start_, items_;
};

double percentile(std::vector<double> values, double q) {
    if (values.empty()) return 0;
    auto at = values.begin() + std::ptrdiff_t(std::floor(q * double(values.size() - 1)));
    std::nth_element(values.begin(), at, values.end());
    return *at;
}

double meshDiagonal(const OrientedPoints& mesh) {
    if (mesh.positions.empty()) return 0;
    Vector3d lo = mesh.positions[0], hi = lo;
    for (const Vector3d& p : mesh.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return (hi - lo).norm();
}

}  // namespace

std::vector<double> distancesToMesh(const OrientedPoints& mesh, const std::vector<Vector3d>& points) {
    TriangleGrid grid(mesh);
    std::vector<double> out(points.size(), INFINITY);
    if (grid.empty()) return out;
    parallelChunks(points.size(), [&](size_t begin, size_t end) {
        std::vector<uint32_t> seen(grid.triangles(), 0);
        for (size_t i = begin; i < end; ++i) out[i] = grid.distance(points[i], seen, uint32_t(i - begin + 1));
    });
    return out;
}

Fidelity measureFidelity(const OrientedPoints& mesh, const std::vector<Vector3d>& points, double tolerance,
                         size_t surfaceSamples, double creaseAngleDeg) {
    Fidelity f;
    f.diagonal = meshDiagonal(mesh);
    f.tolerance = tolerance;
    f.points = points.size();
    double area = 0;
    for (double a : triangleAreas(mesh)) area += a;
    if (!(area > 0)) throw Error("fidelity needs a mesh: the model has no triangles with area");
    if (surfaceSamples == 0) {
        const double spacing = tolerance * f.diagonal / 4;
        surfaceSamples = size_t(std::clamp(area / (spacing * spacing), 1e4, 1e6));
    }
    const std::vector<Vector3d> surface = sampleFaces(mesh, surfaceSamples, 0x1d3a, nullptr, creaseAngleDeg).positions;
    f.surfaceSamples = surface.size();
    if (points.empty()) return f;
    const double within = tolerance * f.diagonal;

    // Surface → points.
    PointCloud cloud{points};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));  // built here
    std::vector<double> gaps(surface.size());
    parallelChunks(surface.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            uint32_t nearest;
            double squared;
            tree.knnSearch(surface[i].data(), 1, &nearest, &squared);
            gaps[i] = std::sqrt(squared);
        }
    });
    // Points → surface.
    std::vector<double> offsets = distancesToMesh(mesh, points);

    auto share = [&](const std::vector<double>& d) {
        return double(std::count_if(d.begin(), d.end(), [&](double x) { return x <= within; })) / double(d.size());
    };
    f.coverage = share(gaps);
    f.accuracy = share(offsets);
    f.coverageP99 = percentile(gaps, 0.99) / f.diagonal;
    f.coverageMax = *std::max_element(gaps.begin(), gaps.end()) / f.diagonal;
    f.accuracyP99 = percentile(offsets, 0.99) / f.diagonal;
    f.accuracyMax = *std::max_element(offsets.begin(), offsets.end()) / f.diagonal;
    return f;
}

}  // namespace ink
