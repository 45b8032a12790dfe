// A uniform grid of stroke points for "is any point of another stroke within r" queries (contour and hatching
// tracing, lines.cpp and hatching.cpp). Header only; no Vulkan.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ink {

// A grid cell's hash key: its three coordinates, 21 bits each (cells wrap every 2²¹ along an axis, far beyond the
// unit-diagonal models the grids hold). The one packing every hashed grid of the CPU code uses.
inline uint64_t cellKey(int x, int y, int z) {
    return (uint64_t(uint32_t(x) & 0x1FFFFF) << 42) | (uint64_t(uint32_t(y) & 0x1FFFFF) << 21) |
           uint64_t(uint32_t(z) & 0x1FFFFF);
}

// Points of strokes in a uniform grid hashed by cell, for "is any point of another stroke within r" queries
// with r at most the cell side (27 cells a query).
class PointHash {
    using Vector3d = Eigen::Vector3d;
    using Vector3f = Eigen::Vector3f;

public:
    struct Entry {
        Vector3f p, n;
        uint32_t stroke;
        float arc;  // signed arc length from the stroke's seed
    };
    explicit PointHash(double cell) : inv_(1.0 / cell) {}

    void add(const Vector3d& p, const Vector3d& n, uint32_t stroke, double arc) {
        cells_[key(cellOf(p))].push_back(uint32_t(entries_.size()));
        entries_.push_back({p.cast<float>(), n.cast<float>(), stroke, float(arc)});
    }
    // Whether a point lies within r of p on the same side of the surface (normals less than ~70° apart; the two
    // sides of a thin part keep their own strokes), skipping the points of `stroke` within `gap` of `arc` along it.
    bool near(const Vector3d& p, const Vector3d& n, double r, uint32_t stroke = UINT32_MAX, double arc = 0,
              double gap = 0) const {
        const Eigen::Array3i c = cellOf(p);
        const Vector3f pf = p.cast<float>(), nf = n.cast<float>();
        const float r2 = float(r * r);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto it = cells_.find(key(c + Eigen::Array3i(dx, dy, dz)));
                    if (it == cells_.end()) continue;
                    for (uint32_t i : it->second) {
                        const Entry& e = entries_[i];
                        if ((e.p - pf).squaredNorm() >= r2 || e.n.dot(nf) < 0.35f) continue;
                        if (e.stroke == stroke && std::abs(double(e.arc) - arc) < gap) continue;
                        return true;
                    }
                }
        return false;
    }
    // Calls f(stroke) for each point within r of p, in the order they were added (r at most the cell side).
    template <typename F>
    void forEachNear(const Vector3d& p, double r, F&& f) const {
        const Eigen::Array3i c = cellOf(p);
        const Vector3f pf = p.cast<float>();
        const float r2 = float(r * r);
        std::vector<uint32_t> hits;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto it = cells_.find(key(c + Eigen::Array3i(dx, dy, dz)));
                    if (it == cells_.end()) continue;
                    for (uint32_t i : it->second)
                        if ((entries_[i].p - pf).squaredNorm() < r2) hits.push_back(i);
                }
        std::sort(hits.begin(), hits.end());
        for (uint32_t i : hits) f(entries_[i].stroke);
    }
    // Removes the entries from `first` on (a stroke just traced and dropped: always the last ones added).
    void truncate(size_t first) {
        for (size_t i = first; i < entries_.size(); ++i) {
            auto& list = cells_[key(cellOf(entries_[i].p.cast<double>()))];
            while (!list.empty() && list.back() >= first) list.pop_back();
        }
        entries_.resize(first);
    }
    size_t size() const { return entries_.size(); }

private:
    Eigen::Array3i cellOf(const Vector3d& p) const { return (p.array() * inv_).floor().cast<int>(); }
    static uint64_t key(const Eigen::Array3i& c) { return cellKey(c.x(), c.y(), c.z()); }
    double inv_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
    std::vector<Entry> entries_;
};

}  // namespace ink
