#include "refine/spacing.h"

#include "base/point_hash.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <queue>
#include <unordered_map>

namespace ink {

namespace {

// A uniform grid over the points for k-nearest-neighbour queries, searched in growing shells of cells.
class PointGrid {
public:
    explicit PointGrid(std::vector<Eigen::Vector3f> points) : points_(std::move(points)) {
        Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
        for (const auto& p : points_) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        Eigen::Vector3f extent = (hi - lo).cwiseMax(1e-9f);
        // Cells of about four points on a surface spanning the box.
        float surface = 2.0f * (extent.x() * extent.y() + extent.y() * extent.z() + extent.z() * extent.x());
        cell_ = std::max(1e-9f, std::sqrt(4.0f * surface / float(std::max<size_t>(1, points_.size()))));
        lo_ = lo;
        maxShell_ = int(std::ceil(extent.maxCoeff() / cell_)) + 1;  // every point is within this many shells
        for (uint32_t i = 0; i < points_.size(); ++i) cells_[key(cellOf(points_[i]))].push_back(i);
    }

    // Distances to the k nearest other points, ascending.
    std::vector<float> nearest(uint32_t i, size_t k) const {
        std::priority_queue<float> best;  // the k smallest squared distances so far (max on top)
        const Eigen::Vector3i c = cellOf(points_[i]);
        for (int shell = 0;; ++shell) {
            for (int dz = -shell; dz <= shell; ++dz)
                for (int dy = -shell; dy <= shell; ++dy)
                    for (int dx = -shell; dx <= shell; ++dx) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != shell) continue;
                        auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
                        if (it == cells_.end()) continue;
                        for (uint32_t j : it->second) {
                            if (j == i) continue;
                            float d2 = (points_[j] - points_[i]).squaredNorm();
                            if (best.size() < k)
                                best.push(d2);
                            else if (d2 < best.top())
                                best.pop(), best.push(d2);
                        }
                    }
            // Points beyond this shell are at least shell·cell away.
            float reach = float(shell) * cell_;
            if ((best.size() == k && best.top() <= reach * reach) || shell > maxShell_) break;
        }
        std::vector<float> out;
        while (!best.empty()) out.push_back(std::sqrt(best.top())), best.pop();
        std::reverse(out.begin(), out.end());
        return out;
    }

    size_t size() const { return points_.size(); }

private:
    Eigen::Vector3i cellOf(const Eigen::Vector3f& p) const { return ((p - lo_) / cell_).array().floor().cast<int>(); }
    static uint64_t key(const Eigen::Vector3i& c) { return cellKey(c.x(), c.y(), c.z()); }

    std::vector<Eigen::Vector3f> points_;
    Eigen::Vector3f lo_;
    float cell_ = 1;
    int maxShell_ = 0;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

std::vector<Eigen::Vector3f> positions(const std::vector<PointRecord>& points, double fraction) {
    std::vector<Eigen::Vector3f> out;
    for (const auto& p : points)
        if (fraction >= 1.0 || p.tone < fraction) out.emplace_back(p.position[0], p.position[1], p.position[2]);
    return out;
}

}  // namespace

double estimateSurfaceArea(const std::vector<PointRecord>& points) {
    constexpr size_t k = 16;
    if (points.size() <= k) return 0;
    PointGrid grid(positions(points, 1.0));
    double sum = 0;
    for (uint32_t i = 0; i < grid.size(); ++i) {
        float r = grid.nearest(i, k).back();
        sum += M_PI * double(r) * double(r);
    }
    return sum / (double(k) - 0.5);
}

SpacingStats measureSpacing(const std::vector<PointRecord>& points, double fraction, double area) {
    SpacingStats s;
    s.fraction = fraction;
    std::vector<Eigen::Vector3f> p = positions(points, fraction);
    s.points = p.size();
    if (p.size() < 2 || !(area > 0)) return s;
    s.rMax = std::sqrt(2.0 * area / (std::sqrt(3.0) * double(p.size())));
    PointGrid grid(std::move(p));
    double sum = 0, least = INFINITY;
    size_t clumped = 0;
    for (uint32_t i = 0; i < grid.size(); ++i) {
        double d = grid.nearest(i, 1).front() / s.rMax;
        sum += d;
        least = std::min(least, d);
        clumped += d < 0.5;
    }
    s.meanNearest = sum / double(grid.size());
    s.minNearest = least;
    s.clumped = double(clumped) / double(grid.size());
    return s;
}

}  // namespace ink
