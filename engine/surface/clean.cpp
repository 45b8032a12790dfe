// Cleaning oriented points for fitting: duplicate merging and farthest-point sampling.
#include "surface/clean.h"

#include "base/parallel.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>

namespace ink {

using Eigen::Vector3d;

namespace {

constexpr size_t kNone = size_t(-1);

// After points were merged or dropped: `newIndex[i]` is point i's new index, or kNone where it was dropped. A
// triangle with a dropped corner, or with two corners merged into one point, is dropped.
void renumberTriangles(std::vector<Triangle>& triangles, const std::vector<size_t>& newIndex) {
    size_t kept = 0;
    for (const Triangle& t : triangles) {
        size_t a = newIndex[t[0]], b = newIndex[t[1]], c = newIndex[t[2]];
        if (a == kNone || b == kNone || c == kNone || a == b || b == c || c == a) continue;
        triangles[kept++] = {uint32_t(a), uint32_t(b), uint32_t(c)};
    }
    triangles.resize(kept);
}

}  // namespace

size_t mergeDuplicates(OrientedPoints& points, double tolerance) {
    std::vector<Vector3d>& pos = points.positions;
    bool moveNormals = points.normals.size() == pos.size();
    bool exact = !(tolerance > 0);  // also catches NaN
    // Cells twice the tolerance wide: a point's tolerance box then overlaps at most two cells per axis, so
    // 8 probes instead of the 27 that tolerance-wide cells need. Cell indices are clamped so far-out or
    // non-finite coordinates cannot overflow the conversion; clamped points share a cell, which costs
    // time but never a wrong answer, because distances are always checked. In exact mode a cell is one
    // position, keyed by the coordinates' bits (with -0 folded into 0).
    // Cells are counted from the data's own corner, not the origin: far from the origin (offset/diagonal
    // beyond about 2e9) x / cellSize passes the clamp below, every point shared one cell and merging became
    // quadratic (152k points: 31 s).
    double cellSize = 2 * tolerance;
    Vector3d origin = Vector3d::Zero();
    for (int a = 0; a < 3; ++a) {
        double lowest = std::numeric_limits<double>::infinity();
        for (const Vector3d& p : pos)
            if (std::isfinite(p[a])) lowest = std::min(lowest, p[a]);
        if (std::isfinite(lowest)) origin[a] = lowest;
    }
    auto cellOf = [&](double x) {
        constexpr double kLimit = 4.0e18;
        double cell = std::floor(x / cellSize);
        return int64_t(std::clamp(std::isnan(cell) ? 0.0 : cell, -kLimit, kLimit));
    };
    using Key = std::array<int64_t, 3>;
    auto keyOf = [&](const Vector3d& p) {
        Key k;
        for (int a = 0; a < 3; ++a)
            k[size_t(a)] = exact ? std::bit_cast<int64_t>(p[a] + 0.0) : cellOf(p[a] - origin[a]);
        return k;
    };
    auto hash = [](const Key& k) {
        uint64_t h = uint64_t(k[0]) * 0x9E3779B97F4A7C15ull;
        h = (h ^ (h >> 29)) + uint64_t(k[1]) * 0xBF58476D1CE4E5B9ull;
        h = (h ^ (h >> 31)) + uint64_t(k[2]) * 0x94D049BB133111EBull;
        return h ^ (h >> 32);
    };
    auto close = [&](const Vector3d& a, const Vector3d& b) {
        // Dividing first keeps tiny tolerances from squaring to zero.
        return exact ? a == b : ((a - b) / tolerance).squaredNorm() <= 1.0;
    };

    // Open addressing from a cell to the latest kept point in it; the cell's other kept points chain
    // through `next`. A slot's key is recomputed from its point rather than stored, halving the memory.
    size_t capacity = 16;
    while (capacity < 2 * pos.size()) capacity *= 2;
    std::vector<size_t> table(capacity, kNone), next;
    next.reserve(pos.size());
    auto slotOf = [&](const Key& key) -> size_t& {
        size_t s = hash(key) & (capacity - 1);
        while (table[s] != kNone && keyOf(pos[table[s]]) != key) s = (s + 1) & (capacity - 1);
        return table[s];
    };

    // Where each point went, for the triangles (only when there are some).
    std::vector<size_t> newIndex(points.triangles.empty() ? 0 : pos.size());
    size_t kept = 0;
    for (size_t i = 0; i < pos.size(); ++i) {
        const Vector3d p = pos[i];
        Key lo = keyOf(p), hi = lo;
        if (!exact) {
            for (size_t a = 0; a < 3; ++a) {
                const double x = p[Eigen::Index(a)] - origin[Eigen::Index(a)];
                lo[a] = cellOf(x - tolerance);
                hi[a] = cellOf(x + tolerance);
            }
        }
        size_t match = kNone;
        for (int64_t x = lo[0]; x <= hi[0] && match == kNone; ++x)
            for (int64_t y = lo[1]; y <= hi[1] && match == kNone; ++y)
                for (int64_t z = lo[2]; z <= hi[2] && match == kNone; ++z)
                    for (size_t j = slotOf({x, y, z}); j != kNone && match == kNone; j = next[j])
                        if (close(pos[j], p)) match = j;
        if (!newIndex.empty()) newIndex[i] = match == kNone ? kept : match;
        if (match != kNone) continue;
        // Kept points are compacted in place (kept <= i), so the table holds output indices.
        pos[kept] = p;
        if (moveNormals) points.normals[kept] = points.normals[i];
        size_t& head = slotOf(keyOf(p));
        next.push_back(head);
        head = kept++;
    }
    size_t merged = pos.size() - kept;
    pos.resize(kept);
    if (moveNormals) points.normals.resize(kept);
    if (!newIndex.empty()) renumberTriangles(points.triangles, newIndex);
    return merged;
}

NearMerge mergeNearPoints(OrientedPoints& points, double tolerance) {
    std::vector<Vector3d>& pos = points.positions;
    std::vector<Vector3d>& nor = points.normals;
    const size_t n = pos.size();
    const double t2 = tolerance * tolerance;
    std::vector<size_t> cluster(n);
    for (size_t i = 0; i < n; ++i) cluster[i] = i;
    // Each point joins the cluster of the first earlier point within the tolerance that heads a cluster (single
    // linkage on the first match: clusters are as small as the creases that make them). The candidates come from
    // a grid of cells two tolerances wide, sorted once: the ball around a point meets at most 2 of them along each
    // axis, 8 in all (a std::map of tolerance-wide cells, 27 look-ups a point, took 5 s at 10⁶ points).
    if (!(tolerance > 0) || n < 2) return {};
    Vector3d lo = pos[0];
    for (const Vector3d& p : pos) lo = lo.cwiseMin(p);
    using Key = std::array<int64_t, 3>;
    const double cell = 2 * tolerance;
    auto keyOf = [&](const Vector3d& p) {
        Key k;
        for (int a = 0; a < 3; ++a) k[size_t(a)] = int64_t(std::min(std::floor((p[a] - lo[a]) / cell), 4.0e18));
        return k;
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = uint64_t(k[0]) * 0x9E3779B97F4A7C15ull ^ uint64_t(k[1]) * 0xC2B2AE3D27D4EB4Full ^
                         uint64_t(k[2]) * 0x165667B19E3779F9ull;
            return size_t(h ^ (h >> 29));
        }
    };
    std::vector<Key> keys(n);
    std::vector<uint32_t> byCell(n);
    for (size_t i = 0; i < n; ++i) keys[i] = keyOf(pos[i]), byCell[i] = uint32_t(i);
    std::sort(byCell.begin(), byCell.end(),
              [&](uint32_t a, uint32_t b) { return std::tie(keys[a], a) < std::tie(keys[b], b); });
    std::unordered_map<Key, std::pair<uint32_t, uint32_t>, KeyHash> cells;  // a cell's range in byCell
    cells.reserve(n);
    for (uint32_t k = 0; k < n;) {
        uint32_t end = k + 1;
        while (end < n && keys[byCell[end]] == keys[byCell[k]]) ++end;
        cells.emplace(keys[byCell[k]], std::make_pair(k, end));
        k = end;
    }
    for (size_t i = 0; i < n; ++i) {
        // The cells the ball meets: along each axis the point's and the one on the nearer side.
        Key k = keys[i], step;
        for (int a = 0; a < 3; ++a) step[size_t(a)] = (pos[i][a] - lo[a]) / cell - double(k[size_t(a)]) < 0.5 ? -1 : 1;
        size_t best = i;
        for (int c = 0; c < 8; ++c) {
            auto it = cells.find(
                {k[0] + ((c & 1) ? step[0] : 0), k[1] + ((c & 2) ? step[1] : 0), k[2] + ((c & 4) ? step[2] : 0)});
            if (it == cells.end()) continue;
            for (uint32_t m = it->second.first; m < it->second.second; ++m) {
                const size_t j = byCell[m];
                if (j >= best) break;  // sorted by index within a cell
                if (cluster[j] == j && (pos[i] - pos[j]).squaredNorm() <= t2) best = j;
            }
        }
        cluster[i] = best;
    }
    std::vector<Vector3d> sum(n, Vector3d::Zero());
    std::vector<size_t> size(n, 0);
    for (size_t i = 0; i < n; ++i) {
        sum[cluster[i]] += nor[i];
        ++size[cluster[i]];
    }
    NearMerge result;
    std::vector<size_t> newIndex(n, kNone);  // of each cluster's first point
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i) {
        if (cluster[i] != i) continue;
        if (size[i] > 1) {
            Vector3d mean = sum[i] / double(size[i]);
            if (!(mean.norm() >= 0.5)) {
                result.dropped += size[i];
                continue;
            }
            result.merged += size[i] - 1;
            nor[i] = mean.normalized();
        }
        pos[kept] = pos[i];
        nor[kept] = nor[i];
        newIndex[i] = kept++;
    }
    pos.resize(kept);
    nor.resize(kept);
    if (!points.triangles.empty()) {
        for (size_t i = 0; i < n; ++i) newIndex[i] = newIndex[cluster[i]];
        renumberTriangles(points.triangles, newIndex);
    }
    return result;
}

std::vector<size_t> farthestPointSample(const std::vector<Vector3d>& positions, size_t count) {
    size_t n = positions.size();
    std::vector<size_t> picked;
    if (count >= n) {
        for (size_t i = 0; i < n; ++i) picked.push_back(i);
        return picked;
    }
    if (count == 0) return picked;
    auto less = [](const Vector3d& a, const Vector3d& b) {
        return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
    };
    size_t first = 0;
    for (size_t i = 1; i < n; ++i)
        if (less(positions[i], positions[first])) first = i;

    // distance[i]: squared distance from i to the nearest picked point; -1 once i is picked.
    std::vector<double> distance(n, std::numeric_limits<double>::infinity());
    picked.reserve(count);
    size_t current = first;
    for (;;) {
        picked.push_back(current);
        distance[current] = -1;
        if (picked.size() == count) break;
        // Over all threads for a large set (a scan's 10⁶ points: 1000 seeds are 10⁹ distances); each chunk's best,
        // combined in chunk order, is the serial loop's.
        std::array<std::pair<size_t, double>, 64> chunkBest;
        const Vector3d at = positions[current];
        const size_t chunks = parallelChunks(n, 1 << 15, [&](size_t begin, size_t end, size_t k) {
            size_t best = n;
            double bestDistance = -1;
            for (size_t i = begin; i < end; ++i) {
                if (distance[i] < 0) continue;
                double d = (positions[i] - at).squaredNorm();
                if (d < distance[i]) distance[i] = d;
                if (distance[i] > bestDistance) {  // strict: ties keep the lowest index
                    bestDistance = distance[i];
                    best = i;
                }
            }
            chunkBest[k] = {best, bestDistance};
        });
        size_t best = n;
        double bestDistance = -1;
        for (size_t k = 0; k < chunks; ++k)
            if (chunkBest[k].second > bestDistance) best = chunkBest[k].first, bestDistance = chunkBest[k].second;
        // Only reachable with NaN coordinates: take the lowest index not yet picked.
        if (best == n)
            best = size_t(std::find_if(distance.begin(), distance.end(), [](double d) { return !(d < 0); }) -
                          distance.begin());
        current = best;
    }
    return picked;
}

}  // namespace ink
