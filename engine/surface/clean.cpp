// Cleaning oriented points for fitting: duplicate merging and farthest-point sampling.
#include "surface/clean.h"

#include "base/common.h"
#include "base/parallel.h"
#include "base/point_tree.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>
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

NearMerge mergeNearPoints(OrientedPoints& points, double tolerance, double opposedTolerance) {
    std::vector<Vector3d>& pos = points.positions;
    std::vector<Vector3d>& nor = points.normals;
    const size_t n = pos.size();
    const double opposed = std::min(opposedTolerance, tolerance), t2 = tolerance * tolerance, o2 = opposed * opposed;
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
    auto hash = [](const Key& k) {
        uint64_t h = uint64_t(k[0]) * 0x9E3779B97F4A7C15ull ^ uint64_t(k[1]) * 0xC2B2AE3D27D4EB4Full ^
                     uint64_t(k[2]) * 0x165667B19E3779F9ull;
        return size_t(h ^ (h >> 29));
    };
    // The points sorted by cell (then index), keys beside them so that the sort reads memory in order.
    struct Entry {
        Key key;
        uint32_t index;
    };
    std::vector<Entry> sorted(n);
    for (size_t i = 0; i < n; ++i) sorted[i] = {keyOf(pos[i]), uint32_t(i)};
    std::sort(sorted.begin(), sorted.end(),
              [](const Entry& a, const Entry& b) { return std::tie(a.key, a.index) < std::tie(b.key, b.index); });
    std::vector<Key> keys(n);
    std::vector<uint32_t> byCell(n);
    for (size_t k = 0; k < n; ++k) keys[sorted[k].index] = sorted[k].key, byCell[k] = sorted[k].index;
    std::vector<Entry>().swap(sorted);
    // Open addressing from a cell to its range [first, end) in byCell: a table of at least twice the cells,
    // the empty slots' first = end = 0 (a real range is never empty).
    struct Slot {
        uint32_t first = 0, end = 0;
    };
    size_t capacity = 16;
    while (capacity < 2 * n) capacity *= 2;
    std::vector<Slot> table(capacity);
    for (uint32_t k = 0; k < n;) {
        uint32_t end = k + 1;
        while (end < n && keys[byCell[end]] == keys[byCell[k]]) ++end;
        size_t s = hash(keys[byCell[k]]) & (capacity - 1);
        while (table[s].end != 0) s = (s + 1) & (capacity - 1);
        table[s] = {k, end};
        k = end;
    }
    auto rangeOf = [&](const Key& key) -> Slot {
        for (size_t s = hash(key) & (capacity - 1);; s = (s + 1) & (capacity - 1)) {
            if (table[s].end == 0) return {};
            if (keys[byCell[table[s].first]] == key) return table[s];
        }
    };
    // The earlier points within the tolerance of each point, on all threads (most points have none), as (i, j)
    // pairs in the order of i then j; then, in order, each point joins the first of them that heads a cluster.
    std::array<std::vector<std::pair<uint32_t, uint32_t>>, 64> near;
    const size_t chunks = parallelChunks(n, 1 << 14, [&](size_t begin, size_t end, size_t chunk) {
        std::vector<uint32_t> found;
        for (size_t i = begin; i < end; ++i) {
            // The cells the ball meets: along each axis the point's and the one on the nearer side.
            Key k = keys[i], step;
            for (int a = 0; a < 3; ++a)
                step[size_t(a)] = (pos[i][a] - lo[a]) / cell - double(k[size_t(a)]) < 0.5 ? -1 : 1;
            found.clear();
            for (int c = 0; c < 8; ++c) {
                const Slot range = rangeOf(
                    {k[0] + ((c & 1) ? step[0] : 0), k[1] + ((c & 2) ? step[1] : 0), k[2] + ((c & 4) ? step[2] : 0)});
                for (uint32_t m = range.first; m < range.end; ++m) {
                    const uint32_t j = byCell[m];
                    if (j >= i) break;  // sorted by index within a cell
                    if ((pos[i] - pos[j]).squaredNorm() <= t2) found.push_back(j);
                }
            }
            std::sort(found.begin(), found.end());
            for (uint32_t j : found) near[chunk].emplace_back(uint32_t(i), j);
        }
    });
    for (size_t c = 0; c < chunks; ++c)
        for (size_t k = 0; k < near[c].size();) {
            const uint32_t i = near[c][k].first;
            for (; k < near[c].size() && near[c][k].first == i; ++k) {
                const uint32_t j = near[c][k].second;
                if (nor[i].dot(nor[j]) < 0 && (pos[i] - pos[j]).squaredNorm() > o2) continue;  // a thin part's sides
                if (cluster[i] == i && cluster[j] == j) cluster[i] = j;
            }
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

namespace {

// The serial definition of farthest-point sampling, every point's distance updated at every pick; kept for
// positions that are not all finite (a box of NaN cannot prune), where it is what the tree would give.
std::vector<size_t> farthestPointSampleFlat(const std::vector<Vector3d>& positions,
                                            const std::vector<Vector3d>* normals, size_t first, size_t count) {
    const size_t n = positions.size();
    std::vector<double> distance(n, std::numeric_limits<double>::infinity());
    std::vector<size_t> picked;
    picked.reserve(count);
    for (size_t current = first;;) {
        picked.push_back(current);
        distance[current] = -1;
        if (picked.size() == count) break;
        size_t best = n;
        double bestDistance = -1;
        for (size_t i = 0; i < n; ++i) {
            if (distance[i] < 0) continue;
            double d = (positions[i] - positions[current]).squaredNorm();
            if (d < distance[i] && (!normals || facesWay((*normals)[i], (*normals)[current]))) distance[i] = d;
            if (distance[i] > bestDistance) best = i, bestDistance = distance[i];  // ties keep the lowest index
        }
        // Only with NaN coordinates: take the lowest index not yet picked.
        if (best == n)
            best = size_t(std::find_if(distance.begin(), distance.end(), [](double d) { return !(d < 0); }) -
                          distance.begin());
        current = best;
    }
    return picked;
}

// Farthest-point sampling over a k-d tree whose nodes keep their box and the largest distance of their points
// to the picked set (with its point): a pick visits only the nodes whose box comes closer to it than their
// largest distance, the pruning of QuickFPS (Han et al. 2023), since no other point's distance can shrink. The
// squared distances are the flat loop's, computed the same way, and ties go to the lowest index as there, so
// the picks are the flat loop's, in the same order (test: points, farthestPointSample).
class FpsTree {
public:
    FpsTree(const std::vector<Vector3d>& positions, const std::vector<Vector3d>* normals)
        : items_(positions.size()), at_(positions.size()) {
        for (size_t i = 0; i < items_.size(); ++i)
            items_[i] = {positions[i], std::numeric_limits<double>::infinity(), uint32_t(i)};
        nodes_.reserve(2 * (items_.size() / kLeaf + 1));
        build(0, uint32_t(items_.size()));
        for (uint32_t k = 0; k < items_.size(); ++k) at_[items_[k].index] = k;
        if (normals)  // in the tree's order, beside the items (none without normals)
            for (const Item& item : items_) normals_.push_back((*normals)[item.index].cast<float>());
    }

    // Picks `i` and brings every distance up to date; returns the next pick (the farthest point).
    size_t pick(size_t i) {
        items_[at_[i]].distance = -1;
        const Vector3d p = items_[at_[i]].p;
        update(0, p, normals_.empty() ? Eigen::Vector3f::Zero() : normals_[at_[i]]);
        return nodes_[0].farthest;
    }

private:
    static constexpr uint32_t kLeaf = 32;
    // The points in the tree's order, beside their distances: a leaf reads one stretch of memory.
    struct Item {
        Vector3d p;
        double distance;  // squared distance to the nearest picked point; -1 once picked
        uint32_t index;   // in the input
    };
    struct Node {
        Vector3d lo, hi;
        uint32_t begin, end, left = 0, right = 0;  // the children's indices; 0 for a leaf
        uint32_t farthest = 0;
        double distance = std::numeric_limits<double>::infinity();
    };

    uint32_t build(uint32_t begin, uint32_t end) {
        const uint32_t index = uint32_t(nodes_.size());
        nodes_.push_back({Vector3d::Zero(), Vector3d::Zero(), begin, end});
        Vector3d lo = items_[begin].p, hi = lo;
        uint32_t farthest = items_[begin].index;
        for (uint32_t k = begin + 1; k < end; ++k) {
            lo = lo.cwiseMin(items_[k].p);
            hi = hi.cwiseMax(items_[k].p);
            farthest = std::min(farthest, items_[k].index);
        }
        nodes_[index].lo = lo;
        nodes_[index].hi = hi;
        nodes_[index].farthest = farthest;  // every distance is infinite: the lowest index
        if (end - begin > kLeaf) {
            int axis;
            (hi - lo).maxCoeff(&axis);
            const uint32_t mid = begin + (end - begin) / 2;
            std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                             [axis](const Item& a, const Item& b) { return a.p[axis] < b.p[axis]; });
            const uint32_t left = build(begin, mid), right = build(mid, end);
            nodes_[index].left = left;
            nodes_[index].right = right;
        }
        return index;
    }

    // Is (d, i) farther than the node's farthest, ties to the lower index?
    static bool farther(double d, uint32_t i, double best, uint32_t bestIndex) {
        return d > best || (d == best && i < bestIndex);
    }

    // `towards`: the pick's normal; with normals, only the points facing its way come nearer it.
    void update(uint32_t index, const Vector3d& at, const Eigen::Vector3f& towards) {
        Node& node = nodes_[index];
        // The box's squared distance from `at`, a lower bound of its points' (less a margin for rounding).
        const Vector3d gap = (node.lo - at).cwiseMax(at - node.hi).cwiseMax(0.0);
        if (gap.squaredNorm() * (1 - 1e-12) > node.distance) return;
        double best = -1;
        uint32_t bestIndex = uint32_t(-1);
        if (node.left == 0) {
            for (uint32_t k = node.begin; k < node.end; ++k) {
                Item& item = items_[k];
                if (item.distance < 0) continue;
                if (normals_.empty() || facesWay(normals_[k], towards))
                    item.distance = std::min(item.distance, (item.p - at).squaredNorm());
                if (farther(item.distance, item.index, best, bestIndex)) best = item.distance, bestIndex = item.index;
            }
        } else {
            const uint32_t left = node.left, right = node.right;
            update(left, at, towards);
            update(right, at, towards);
            const Node &a = nodes_[left], &b = nodes_[right];
            best = a.distance, bestIndex = a.farthest;
            if (farther(b.distance, b.farthest, best, bestIndex)) best = b.distance, bestIndex = b.farthest;
        }
        nodes_[index].distance = best;
        nodes_[index].farthest = bestIndex;
    }

    std::vector<Item> items_;
    std::vector<uint32_t> at_;  // each input point's place in items_
    std::vector<Node> nodes_;
    std::vector<Eigen::Vector3f> normals_;  // the items' normals, with normals
};

}  // namespace

std::vector<size_t> farthestPointSample(const std::vector<Vector3d>& positions, size_t count,
                                        const std::vector<Vector3d>* normals) {
    size_t n = positions.size();
    if (normals && normals->size() != n) throw Error("farthestPointSample: one normal a position");
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
    if (n >= size_t(UINT32_MAX) ||
        !std::all_of(positions.begin(), positions.end(), [](const Vector3d& p) { return p.allFinite(); }))
        return farthestPointSampleFlat(positions, normals, first, count);

    FpsTree tree(positions, normals);
    picked.reserve(count);
    for (size_t current = first;;) {
        picked.push_back(current);
        if (picked.size() == count) break;
        current = tree.pick(current);
    }
    return picked;
}

size_t removeOutliers(OrientedPoints& points) {
    const size_t m = points.positions.size(), k = kOutlierNeighbours;
    if (!points.triangles.empty() || m <= 8 * k) return 0;
    const PointCloud cloud{points.positions};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    std::vector<float> spacing(m, 0.0f);
    std::vector<uint32_t> neighbours(m * k, 0);
    parallelChunks(m, 4096, [&](size_t begin, size_t end, size_t) {
        std::array<uint32_t, kOutlierNeighbours + 1> index{};
        std::array<double, kOutlierNeighbours + 1> squared{};
        for (size_t i = begin; i < end; ++i) {
            const size_t found = tree.knnSearch(points.positions[i].data(), k + 1, index.data(), squared.data());
            double sum = 0;
            size_t used = 0;
            for (size_t j = 0; j < found && used < k; ++j) {
                if (index[j] == i) continue;
                sum += std::sqrt(squared[j]);
                neighbours[i * k + used++] = index[j];
            }
            for (size_t j = used; j < k; ++j) neighbours[i * k + j] = uint32_t(i);
            spacing[i] = used > 0 ? float(sum / double(used)) : 0.0f;
        }
    });
    auto median = [](std::vector<float> v) {
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    const float global = median(spacing);
    std::vector<char> outlier(m, 0);
    parallelChunks(m, 4096, [&](size_t begin, size_t end, size_t) {
        std::vector<float> around(k);
        for (size_t i = begin; i < end; ++i) {
            for (size_t j = 0; j < k; ++j) around[j] = spacing[neighbours[i * k + j]];
            const float local = median(around);
            outlier[i] = (local > 0 && spacing[i] > float(kOutlierLocal) * local) ||
                         (global > 0 && spacing[i] > float(kOutlierGlobal) * global);
        }
    });
    // Clumps: the points left, in parts linked by their nearest neighbours; a part of fewer than kOutlierClump
    // points floats alone (a scan's floaters: CGAL's poste_france.xyz had clumps of 7 to 41 points 90 units off,
    // which framed the drawing so that its body came out 100 pixels wide) unless it lies within kClumpGap times
    // the cloud's median spacing of the body (the parts of kOutlierClump points and more) or of a clump kept so: a
    // scan's fragments across a gap stay, floaters beside floaters go (poste_france's pair of 24 and 17 points,
    // 1.8 units apart, each kept the other).
    std::vector<uint32_t> part(m);
    for (uint32_t i = 0; i < m; ++i) part[i] = i;
    const auto root = [&](uint32_t i) {
        while (part[i] != i) i = part[i] = part[part[i]];
        return i;
    };
    for (uint32_t i = 0; i < m; ++i)
        for (size_t j = 0; j < k; ++j) {
            const uint32_t o = neighbours[i * k + j];
            if (outlier[i] || outlier[o]) continue;
            const uint32_t a = root(i), b = root(o);
            if (a != b) part[std::max(a, b)] = std::min(a, b);
        }
    std::vector<uint32_t> size(m, 0);
    for (uint32_t i = 0; i < m; ++i)
        if (!outlier[i]) ++size[root(i)];
    std::map<uint32_t, std::vector<uint32_t>> clumps;
    constexpr uint32_t kBody = std::numeric_limits<uint32_t>::max();
    for (uint32_t i = 0; i < m; ++i)
        if (!outlier[i] && size[root(i)] < kOutlierClump) clumps[root(i)].push_back(i);
    // Distances that overflow (a cloud at 1e200) measure nothing; and clumps are a few stray points, never most.
    size_t inClumps = 0;
    for (const auto& [id, members] : clumps) inClumps += members.size();
    if (!(global > 0 && std::isfinite(global)) || 2 * inClumps >= m) clumps.clear();
    // Each clump's neighbouring parts within reach (kBody for the body: then no other matters). Its nearest point
    // outside is among its points' (size + 1) nearest: where that is the body's, within reach, no radius search
    // (which may gather thousands of the body's points) is needed.
    const double reach = kClumpGap * double(global);
    std::map<uint32_t, std::vector<uint32_t>> near;  // by part id: ordered, so the rounds below are deterministic
    bool byBody = false;
    for (const auto& [id, members] : clumps) {
        std::vector<uint32_t>& parts = near[id];
        std::vector<uint32_t> index(members.size() + 1);
        std::vector<double> squared(members.size() + 1);
        for (uint32_t i : members) {
            const size_t found =
                tree.knnSearch(points.positions[i].data(), members.size() + 1, index.data(), squared.data());
            for (size_t j = 0; j < found && parts.empty(); ++j)
                if (!outlier[index[j]] && root(index[j]) != id && squared[j] <= reach * reach &&
                    size[root(index[j])] >= kOutlierClump)
                    parts.assign(1, kBody);
            if (!parts.empty()) break;
        }
        if (!parts.empty()) {
            byBody = true;
            continue;
        }
        std::vector<std::pair<uint32_t, double>> hits;
        for (uint32_t i : members) {
            tree.radiusSearch(points.positions[i].data(), reach * reach, hits, nanoflann::SearchParams());
            for (const auto& hit : hits) {
                const uint32_t other = hit.first;
                if (outlier[other] || root(other) == id) continue;
                if (size[root(other)] >= kOutlierClump) {
                    parts.assign(1, kBody);
                    byBody = true;
                    break;
                }
                if (std::find(parts.begin(), parts.end(), root(other)) == parts.end()) parts.push_back(root(other));
            }
            if (!parts.empty() && parts[0] == kBody) break;
        }
    }
    // Kept: by the body, or by a kept clump, in rounds until none is added.
    std::set<uint32_t> keptClumps;
    for (bool grew = byBody; grew;) {
        grew = false;
        for (const auto& [id, parts] : near)
            if (!keptClumps.count(id) && std::any_of(parts.begin(), parts.end(),
                                                     [&](uint32_t o) { return o == kBody || keptClumps.count(o) > 0; }))
                grew = keptClumps.insert(id).second;
    }
    for (const auto& [id, members] : clumps)
        if (!keptClumps.count(id))
            for (uint32_t i : members) outlier[i] = 1;
    size_t kept = 0;
    for (size_t i = 0; i < m; ++i) {
        if (outlier[i]) continue;
        points.positions[kept] = points.positions[i];
        points.normals[kept] = points.normals[i];
        ++kept;
    }
    points.positions.resize(kept);
    points.normals.resize(kept);
    return m - kept;
}

namespace {

// The quadric z = a x² + b xy + c y² + d x + e y + f fitted (weighted least squares) to points in the frame of their
// weighted tangent plane: the centroid, u and v along the two largest spreads, n across.
struct LocalQuadric {
    Eigen::Vector3d centroid, u, v, n;
    Eigen::Matrix<double, 6, 1> c;
    double height(double x, double y) const {
        return c[0] * x * x + c[1] * x * y + c[2] * y * y + c[3] * x + c[4] * y + c[5];
    }
    // How far p lies off the quadric, along n.
    double offset(const Eigen::Vector3d& p) const {
        const Eigen::Vector3d d = p - centroid;
        return d.dot(n) - height(d.dot(u), d.dot(v));
    }
    // p moved along n onto the quadric; `normal` gets the quadric's unit normal there.
    Eigen::Vector3d onto(const Eigen::Vector3d& p, Eigen::Vector3d& normal) const {
        const Eigen::Vector3d d = p - centroid;
        const double x = d.dot(u), y = d.dot(v);
        normal = (n - (2 * c[0] * x + c[1] * y + c[3]) * u - (c[1] * x + 2 * c[2] * y + c[4]) * v).normalized();
        return centroid + x * u + y * v + height(x, y) * n;
    }
};

// None where the points do not hold a quadric (too few, all on a line).
std::optional<LocalQuadric> fitLocalQuadric(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& w) {
    LocalQuadric q;
    double total = 0;
    q.centroid.setZero();
    for (size_t k = 0; k < points.size(); ++k) q.centroid += w[k] * points[k], total += w[k];
    q.centroid /= total;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector3d d = points[k] - q.centroid;
        covariance += w[k] * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> frame(covariance);  // ascending
    q.n = frame.eigenvectors().col(0);
    q.v = frame.eigenvectors().col(1);
    q.u = frame.eigenvectors().col(2);
    Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector3d d = points[k] - q.centroid;
        const double x = d.dot(q.u), y = d.dot(q.v);
        Eigen::Matrix<double, 6, 1> row;
        row << x * x, x * y, y * y, x, y, 1.0;
        normal += w[k] * row * row.transpose();
        rhs += w[k] * d.dot(q.n) * row;
    }
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(normal);
    if (solver.info() != Eigen::Success || !(solver.rcond() > 1e-12)) return std::nullopt;
    q.c = solver.solve(rhs);
    if (!q.c.allFinite()) return std::nullopt;
    return q;
}

}  // namespace

// Whether neighbour j lies on point i's side: their normals turn by at most 90° (a normal not known, zero, agrees).
static bool sameSide(const std::vector<Eigen::Vector3d>& normals, size_t i, size_t j) {
    return normals[i].dot(normals[j]) >= 0;
}

double scanNoise(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals) {
    const size_t m = positions.size(), k = kNoiseNeighbours + 1;
    if (m <= 2 * k) return 0.0;
    const PointCloud cloud{positions};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    const size_t step = std::max<size_t>(1, m / kNoiseSamples), count = (m + step - 1) / step;
    std::vector<double> ratio(count, -1.0);
    parallelChunks(count, 256, [&](size_t begin, size_t end, size_t) {
        std::vector<uint32_t> index(k);
        std::vector<double> squared(k);
        std::vector<Eigen::Vector3d> around;
        std::vector<double> ones;
        for (size_t s = begin; s < end; ++s) {
            const size_t i = s * step;
            const size_t found = tree.knnSearch(positions[i].data(), k, index.data(), squared.data());
            if (found < k) continue;
            around.clear();
            double spacing = 0;
            size_t near = 0;
            for (size_t j = 0; j < found; ++j) {
                if (index[j] == i || !sameSide(normals, i, index[j])) continue;
                around.push_back(positions[index[j]]);
                if (near < 8) spacing += std::sqrt(squared[j]), ++near;
            }
            spacing /= double(std::max<size_t>(near, 1));
            if (!(spacing > 0) || around.size() < kNoiseNeighbours / 2) continue;
            ones.assign(around.size(), 1.0);
            if (const auto q = fitLocalQuadric(around, ones)) ratio[s] = std::abs(q->offset(positions[i])) / spacing;
        }
    });
    ratio.erase(std::remove(ratio.begin(), ratio.end(), -1.0), ratio.end());
    if (ratio.empty()) return 0.0;
    std::nth_element(ratio.begin(), ratio.begin() + std::ptrdiff_t(ratio.size() / 2), ratio.end());
    return ratio[ratio.size() / 2];
}

size_t smoothNeighbours(double noise) { return size_t(std::clamp(std::round(64.0 * noise / 0.28), 64.0, 128.0)); }

double smoothScan(std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals, size_t neighbours) {
    const size_t m = positions.size(), k = neighbours;
    if (m <= k) return 0.0;
    const std::vector<Eigen::Vector3d> original = positions;
    for (size_t round = 0; round < kSmoothRounds; ++round) {
        const std::vector<Eigen::Vector3d> from = positions, facing = normals;
        const PointCloud cloud{from};
        const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
        parallelChunks(m, 1024, [&](size_t begin, size_t end, size_t) {
            std::vector<uint32_t> index(k);
            std::vector<double> squared(k), w;
            std::vector<Eigen::Vector3d> around;
            for (size_t i = begin; i < end; ++i) {
                const size_t found = tree.knnSearch(from[i].data(), k, index.data(), squared.data());
                if (found < k) continue;
                const double h2 = squared[found - 1];
                if (!(h2 > 0)) continue;
                around.clear();
                w.clear();
                for (size_t j = 0; j < found; ++j) {
                    if (!sameSide(facing, i, index[j])) continue;
                    around.push_back(from[index[j]]);
                    w.push_back(std::exp(-2.0 * squared[j] / h2));
                }
                if (around.size() < k / 2) continue;
                const auto q = fitLocalQuadric(around, w);
                if (!q) continue;
                Eigen::Vector3d g;
                const Eigen::Vector3d moved = q->onto(from[i], g);
                if (!moved.allFinite() || !g.allFinite()) continue;
                positions[i] = moved;
                normals[i] = g.dot(facing[i]) < 0 ? -g : g;
            }
        });
    }
    std::vector<double> moved(m);
    for (size_t i = 0; i < m; ++i) moved[i] = (positions[i] - original[i]).norm();
    std::nth_element(moved.begin(), moved.begin() + std::ptrdiff_t(m / 2), moved.end());
    return moved[m / 2];
}

bool normalsPointInward(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals) {
    if (positions.empty()) return false;
    const size_t k = std::clamp<size_t>(positions.size() / 64, 1, kOutermost);
    size_t inward = 0, outward = 0;
    std::vector<std::pair<double, size_t>> along(positions.size());
    for (int axis = 0; axis < 3; ++axis)
        for (double side : {-1.0, 1.0}) {
            for (size_t i = 0; i < positions.size(); ++i) along[i] = {-side * positions[i][axis], i};
            std::partial_sort(along.begin(), along.begin() + std::ptrdiff_t(k), along.end());
            for (size_t j = 0; j < k; ++j) {
                const double lean = side * normals[along[j].second][axis];
                inward += lean < -0.3;
                outward += lean > 0.3;
            }
        }
    return inward > 3 * outward;
}

namespace {

// Prim's tree over `around` from the points already `reached` (their neighbours first), then from each unreached
// part's extreme point along x (`byX`), that point's normal turned to face +x; each point reached is turned to agree
// with the one it is reached from, weights 1 − |nᵢ·nⱼ| (ties by index: deterministic). Returns the flips.
size_t growOrientation(const std::vector<std::vector<uint32_t>>& around, const std::vector<uint32_t>& byX,
                       std::vector<Vector3d>& normals, std::vector<char>& reached) {
    using Item = std::tuple<double, uint32_t, uint32_t>;  // weight, point, the point it is reached from
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    size_t flipped = 0;
    const auto grow = [&] {
        while (!queue.empty()) {
            const auto [weight, i, from] = queue.top();
            queue.pop();
            if (i != from) {
                if (reached[i]) continue;
                reached[i] = 1;
                if (normals[i].dot(normals[from]) < 0) normals[i] = -normals[i], ++flipped;
            }
            for (uint32_t j : around[i])
                if (!reached[j]) queue.push({1.0 - std::abs(normals[i].dot(normals[j])), j, i});
        }
    };
    for (uint32_t i = 0; i < reached.size(); ++i)
        if (reached[i]) queue.push({0.0, i, i});
    grow();
    for (uint32_t root : byX) {
        if (reached[root]) continue;
        reached[root] = 1;
        if (normals[root].x() < 0) normals[root] = -normals[root], ++flipped;  // on the hull: facing +x
        queue.push({0.0, root, root});
        grow();
    }
    return flipped;
}

}  // namespace

size_t orientNormals(const std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals,
                     const std::vector<char>& estimated) {
    const size_t m = positions.size();
    constexpr size_t kNeighbours = 8, kScreenPoints = 20000;
    if (m <= kNeighbours + 1) return 0;
    const bool anyEstimated = std::find(estimated.begin(), estimated.end(), 1) != estimated.end();
    const auto isEstimated = [&](size_t i) { return anyEstimated && estimated[i]; };
    const PointCloud cloud{positions};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    // Point i's neighbours along the surface, up to kNeighbours into `out`; counts its pairs and opposed ones.
    // `given`: only points whose normals the file gave, signs telling; else every point, signs not considered.
    const auto along = [&](size_t i, bool given, uint32_t* out, size_t& pairs, size_t& opposed) {
        std::array<uint32_t, kNeighbours + 1> index{};
        std::array<double, kNeighbours + 1> squared{};
        const size_t found = tree.knnSearch(positions[i].data(), kNeighbours + 1, index.data(), squared.data());
        size_t used = 0;
        for (size_t k = 0; k < found && used < kNeighbours; ++k) {
            if (index[k] == i || (given && isEstimated(index[k]))) continue;
            // Only neighbours along the surface, not across it: the two sides of a thin part face apart
            // rightly (each lies behind the other's tangent plane: a = nᵢ·d̂ and b = nⱼ·d̂ of opposite signs,
            // both clear of 0; the walls of a narrow gap face each other, the same), and the tree must not
            // turn one to agree with the other. A flipped normal on one sheet gives a and b the same sign.
            const Eigen::Vector3d d = positions[index[k]] - positions[i];
            const double length = d.norm();
            if (!(length > 0)) continue;
            const double a = normals[i].dot(d) / length, b = normals[index[k]].dot(d) / length;
            if (std::abs(a) > 0.5 || std::abs(b) > 0.5 ||
                (given && a * b < 0 && std::abs(a) > 0.05 && std::abs(b) > 0.05))
                continue;
            if (out) out[used] = index[k];
            ++used;
            ++pairs;
            opposed += normals[i].dot(normals[index[k]]) < -0.5;
        }
    };
    // The graph both ways: j among i's nearest, or i among j's.
    const auto graph = [&](const std::vector<uint32_t>& neighbours) {
        std::vector<std::vector<uint32_t>> around(m);
        for (size_t i = 0; i < m; ++i)
            for (size_t k = 0; k < kNeighbours; ++k) {
                const uint32_t j = neighbours[i * kNeighbours + k];
                if (j == UINT32_MAX) continue;
                around[i].push_back(j);
                around[j].push_back(uint32_t(i));
            }
        return around;
    };
    std::vector<uint32_t> byX(m);
    for (uint32_t i = 0; i < m; ++i) byX[i] = i;
    std::stable_sort(byX.begin(), byX.end(),
                     [&](uint32_t a, uint32_t b) { return positions[a].x() > positions[b].x(); });

    // The normals the file gave: turned to agree where more than 5% of their pairs are opposed.
    const auto orientGiven = [&]() -> size_t {
        // A large cloud is screened first on every stride-th point: where under half the share that decides is
        // opposed there (a scan with consistent normals), the full pass is not needed (1M points: 2.4 → 0.4 s).
        if (m > 2 * kScreenPoints) {
            const size_t stride = m / kScreenPoints;
            size_t pairs = 0, opposed = 0;
            for (size_t i = 0; i < m; i += stride)
                if (!isEstimated(i)) along(i, true, nullptr, pairs, opposed);
            if (opposed * 40 <= pairs) return 0;
        }
        std::vector<uint32_t> neighbours(m * kNeighbours, UINT32_MAX);
        std::vector<size_t> opposedIn(64, 0), pairsIn(64, 0);
        const size_t chunks = parallelChunks(m, 1024, [&](size_t begin, size_t end, size_t chunk) {
            for (size_t i = begin; i < end; ++i)
                if (!isEstimated(i)) along(i, true, &neighbours[i * kNeighbours], pairsIn[chunk], opposedIn[chunk]);
        });
        size_t opposed = 0, pairs = 0;
        for (size_t c = 0; c < chunks; ++c) opposed += opposedIn[c], pairs += pairsIn[c];
        if (opposed * 20 <= pairs) return 0;
        // The estimated points are not part of this tree: marked reached, and without edges in its graph, so that
        // growing from them reaches nothing.
        std::vector<char> reached(m, 0);
        for (size_t i = 0; i < m; ++i) reached[i] = isEstimated(i);
        return growOrientation(graph(neighbours), byX, normals, reached);
    };
    if (!anyEstimated) return orientGiven();
    const size_t missing = size_t(std::count(estimated.begin(), estimated.end(), 1));
    // A few estimated (a file's stray zero normals): the given ones oriented among themselves, then held while the
    // tree grows from them into the estimated ones. Many (the given ones too sparse to hold together): one tree over
    // every point, signs of neither telling, and then the whole turned to the side most given normals face.
    const bool few = missing * 10 <= m;
    const size_t flippedGiven = few ? orientGiven() : 0;
    const std::vector<Vector3d> given = few ? std::vector<Vector3d>() : normals;
    std::vector<uint32_t> neighbours(m * kNeighbours, UINT32_MAX);
    parallelChunks(m, 1024, [&](size_t begin, size_t end, size_t) {
        size_t pairs = 0, opposed = 0;
        for (size_t i = begin; i < end; ++i) along(i, false, &neighbours[i * kNeighbours], pairs, opposed);
    });
    std::vector<char> reached(m, 0);
    if (few)
        for (size_t i = 0; i < m; ++i) reached[i] = !estimated[i];
    growOrientation(graph(neighbours), byX, normals, reached);
    if (few) return flippedGiven;
    size_t agree = 0, differ = 0;
    for (size_t i = 0; i < m; ++i)
        if (!estimated[i]) ++(normals[i].dot(given[i]) > 0 ? agree : differ);
    if (differ > agree) {
        for (Vector3d& n : normals) n = -n;
        std::swap(agree, differ);
    }
    return differ;
}

size_t estimateNormals(const std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& normals,
                       std::vector<char>& estimated) {
    const size_t m = positions.size();
    estimated.assign(m, 0);
    size_t missing = 0;
    for (size_t i = 0; i < m; ++i) missing += estimated[i] = normals[i].squaredNorm() == 0;
    if (missing == 0) return 0;
    if (m < kNormalNeighbours)
        throw Error(std::to_string(missing) + (missing == 1 ? " point" : " points") + " of " + std::to_string(m) +
                    (missing == 1 ? " has" : " have") + " no normal, and " + std::to_string(m) +
                    " points are too few to estimate " + (missing == 1 ? "it" : "them") + " from (" +
                    std::to_string(kNormalNeighbours) + " are needed)");
    const PointCloud cloud{positions};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    parallelChunks(m, 1024, [&](size_t begin, size_t end, size_t) {
        std::array<uint32_t, kNormalNeighbours> index{};
        std::array<double, kNormalNeighbours> squared{};
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
        for (size_t i = begin; i < end; ++i) {
            if (!estimated[i]) continue;
            const size_t found = tree.knnSearch(positions[i].data(), kNormalNeighbours, index.data(), squared.data());
            Vector3d centroid = Vector3d::Zero();
            for (size_t k = 0; k < found; ++k) centroid += positions[index[k]];
            centroid /= double(found);
            Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
            for (size_t k = 0; k < found; ++k) {
                const Vector3d d = positions[index[k]] - centroid;
                covariance += d * d.transpose();
            }
            solver.compute(covariance);
            // Eigenvalues ascending: the first eigenvector is the direction of least variance. (Neighbours at one
            // place would leave the covariance zero and the solver's first axis; the fit merges duplicates first.)
            const Vector3d n = solver.eigenvectors().col(0);
            normals[i] = n.allFinite() && n.squaredNorm() > 0.5 ? n.normalized() : Vector3d::UnitX();
        }
    });
    return missing;
}

}  // namespace ink
