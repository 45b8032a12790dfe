#include "vector/path_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace ink {

double PlotPath::length() const {
    if (circle()) {
        double sum = 2.0 * (radius - ringRadius(rings));  // in and out along the radius
        for (uint32_t k = 0; k <= rings; ++k) sum += 2.0 * M_PI * ringRadius(k);
        return sum;
    }
    double sum = 0;
    for (size_t i = 1; i < points.size(); ++i) sum += glm::distance(points[i - 1], points[i]);
    return sum;
}

void PlotPath::reverse() {
    if (!circle()) std::reverse(points.begin(), points.end());
}

double travel(const std::vector<PlotPath>& paths, glm::dvec2 home) {
    double sum = 0;
    glm::dvec2 at = home;
    for (const PlotPath& p : paths) {
        sum += glm::distance(at, p.start());
        at = p.end();
    }
    return sum;
}

namespace {

constexpr int kNeighbours = 8;  // candidates a path end tries in 2-opt
constexpr int kMaxPasses = 16;
constexpr uint32_t kFullTwoOpt = 1000;  // up to this many paths, 2-opt tries every move

// A uniform grid over points, about two a cell, for nearest-point queries. Points are removed as they are
// used; the grid is rebuilt coarser when few remain, so that a query never walks a mostly empty grid.
class PointGrid {
public:
    PointGrid(const std::vector<glm::dvec2>& points, std::vector<uint32_t> ids) : points_(points) { build(ids); }

    // The nearest live point to q (ties: the lower id); UINT32_MAX when none is left.
    uint32_t nearest(glm::dvec2 q) {
        if (live_ == 0) return UINT32_MAX;
        glm::ivec2 c = cellOf(q);
        uint32_t best = UINT32_MAX;
        double bestD = std::numeric_limits<double>::infinity();
        int maxRing = std::max(side_.x, side_.y);
        for (int r = 0; r <= maxRing + 1; ++r) {
            for (int y = c.y - r; y <= c.y + r; ++y) {
                if (y < 0 || y >= side_.y) continue;
                bool edgeRow = y == c.y - r || y == c.y + r;
                for (int x = c.x - r; x <= c.x + r; x += edgeRow ? 1 : 2 * std::max(r, 1)) {
                    if (x < 0 || x >= side_.x) continue;
                    std::vector<uint32_t>& cell = cells_[size_t(y) * size_t(side_.x) + size_t(x)];
                    // Dead entries are dropped as they are met.
                    size_t kept = 0;
                    for (uint32_t id : cell) {
                        if (dead_[id]) continue;
                        cell[kept++] = id;
                        double d = glm::distance(points_[id], q);
                        if (d < bestD || (d == bestD && id < best)) bestD = d, best = id;
                    }
                    cell.resize(kept);
                    if (r == 0) break;
                }
            }
            // Points in ring r + 1 and beyond are at least r cells away.
            if (best != UINT32_MAX && bestD <= double(r) * cell_) break;
        }
        return best;
    }

    void remove(uint32_t id) {
        if (dead_[id]) return;
        dead_[id] = 1;
        if (--live_ * 8 < cells_.size() && cells_.size() > 64) {
            std::vector<uint32_t> ids;
            for (const auto& cell : cells_)
                for (uint32_t i : cell)
                    if (!dead_[i]) ids.push_back(i);
            std::sort(ids.begin(), ids.end());
            build(ids);
        }
    }

private:
    void build(const std::vector<uint32_t>& ids) {
        if (dead_.size() != points_.size()) dead_.assign(points_.size(), 1);
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (uint32_t id : ids) {
            lo = glm::min(lo, points_[id]);
            hi = glm::max(hi, points_[id]);
            dead_[id] = 0;
        }
        live_ = ids.size();
        if (ids.empty()) lo = hi = glm::dvec2(0);
        glm::dvec2 extent = glm::max(hi - lo, glm::dvec2(1e-9));
        cell_ = std::max(std::sqrt(extent.x * extent.y * 2.0 / double(std::max<size_t>(ids.size(), 1))),
                         std::max(extent.x, extent.y) / 4096.0);
        origin_ = lo;
        side_ = glm::ivec2(glm::min(glm::floor(extent / cell_) + 1.0, glm::dvec2(4096)));
        cells_.assign(size_t(side_.x) * size_t(side_.y), {});
        for (uint32_t id : ids) cells_[cellIndex(points_[id])].push_back(id);
    }
    glm::ivec2 cellOf(glm::dvec2 p) const {
        glm::dvec2 c = glm::floor((p - origin_) / cell_);
        return glm::ivec2(glm::clamp(c, glm::dvec2(0), glm::dvec2(side_ - 1)));
    }
    size_t cellIndex(glm::dvec2 p) const {
        glm::ivec2 c = cellOf(p);
        return size_t(c.y) * size_t(side_.x) + size_t(c.x);
    }

    const std::vector<glm::dvec2>& points_;
    std::vector<uint8_t> dead_;
    std::vector<std::vector<uint32_t>> cells_;
    glm::dvec2 origin_{0};
    glm::ivec2 side_{1, 1};
    double cell_ = 1;
    size_t live_ = 0;
};

// For every point of `ids`, the kNeighbours nearest points of `ids` on other paths (id >> 1), nearest first
// (ties: the lower id), into out[id * kNeighbours ...] (UINT32_MAX where there are fewer). The grid is flat
// (the ids sorted by cell) and the points are queried cell by cell, so that a query's cells are in cache.
void nearestNeighbours(const std::vector<glm::dvec2>& points, const std::vector<uint32_t>& ids,
                       std::vector<uint32_t>& out) {
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (uint32_t id : ids) lo = glm::min(lo, points[id]), hi = glm::max(hi, points[id]);
    const glm::dvec2 extent = glm::max(hi - lo, glm::dvec2(1e-9));
    const double cell = std::max(std::sqrt(extent.x * extent.y * 2.0 / double(std::max<size_t>(ids.size(), 1))),
                                 std::max(extent.x, extent.y) / 4096.0);
    const glm::ivec2 side(glm::min(glm::floor(extent / cell) + 1.0, glm::dvec2(4096)));
    auto cellOf = [&](glm::dvec2 p) {
        return glm::ivec2(glm::clamp(glm::floor((p - lo) / cell), glm::dvec2(0), glm::dvec2(side - 1)));
    };
    auto index = [&](glm::ivec2 c) { return size_t(c.y) * size_t(side.x) + size_t(c.x); };
    std::vector<uint32_t> start(size_t(side.x) * size_t(side.y) + 1, 0), sorted(ids.size());
    for (uint32_t id : ids) ++start[index(cellOf(points[id])) + 1];
    for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    {
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t id : ids) sorted[fill[index(cellOf(points[id]))]++] = id;
    }
    const int maxRing = std::max(side.x, side.y);
    for (uint32_t id : sorted) {
        const glm::dvec2 q = points[id];
        const glm::ivec2 c = cellOf(q);
        std::pair<double, uint32_t> best[kNeighbours];
        int count = 0;
        for (int r = 0; r <= maxRing + 1; ++r) {
            for (int y = std::max(c.y - r, 0); y <= std::min(c.y + r, side.y - 1); ++y) {
                const bool edgeRow = y == c.y - r || y == c.y + r;
                for (int x = c.x - r; x <= c.x + r; x += edgeRow ? 1 : 2 * std::max(r, 1)) {
                    if (x < 0 || x >= side.x) continue;
                    const size_t k = index({x, y});
                    for (uint32_t i = start[k]; i < start[k + 1]; ++i) {
                        const uint32_t other = sorted[i];
                        if ((other >> 1) == (id >> 1)) continue;
                        std::pair<double, uint32_t> candidate{glm::distance(points[other], q), other};
                        if (count == kNeighbours && !(candidate < best[count - 1])) continue;
                        int at = count < kNeighbours ? count++ : count - 1;
                        for (; at > 0 && candidate < best[at - 1]; --at) best[at] = best[at - 1];
                        best[at] = candidate;
                    }
                    if (r == 0) break;
                }
            }
            // Points in ring r + 1 and beyond are at least r cells away.
            if (count == kNeighbours && best[count - 1].first <= double(r) * cell) break;
        }
        for (int k = 0; k < kNeighbours; ++k)
            out[size_t(id) * kNeighbours + size_t(k)] = k < count ? best[k].second : UINT32_MAX;
    }
}

}  // namespace

void orderPaths(std::vector<PlotPath>& paths, glm::dvec2 home) {
    const uint32_t n = uint32_t(paths.size());
    if (n < 2) return;
    // Path end 2p is path p's start as given, 2p + 1 its end.
    std::vector<glm::dvec2> ends(2 * size_t(n));
    for (uint32_t p = 0; p < n; ++p) ends[2 * p] = paths[p].start(), ends[2 * p + 1] = paths[p].end();
    // The grids hold both ends of a polyline and one of a circle (its start is its end).
    std::vector<uint32_t> all;
    all.reserve(ends.size());
    for (uint32_t p = 0; p < n; ++p) {
        all.push_back(2 * p);
        if (!paths[p].circle()) all.push_back(2 * p + 1);
    }

    // Each path end's nearest ends of other paths (the geometry does not change, only which end is which).
    std::vector<uint32_t> neighbours(ends.size() * kNeighbours, UINT32_MAX);
    nearestNeighbours(ends, all, neighbours);

    // Greedy nearest neighbour from home.
    std::vector<uint32_t> order;
    std::vector<uint8_t> reversed(n, 0);
    order.reserve(n);
    {
        PointGrid grid(ends, all);
        glm::dvec2 at = home;
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t id = grid.nearest(at);
            uint32_t p = id >> 1;
            reversed[p] = uint8_t(id & 1u);
            order.push_back(p);
            grid.remove(2 * p);
            grid.remove(2 * p + 1);
            at = ends[id ^ 1u];
        }
    }

    // 2-opt: reversing the run of paths at positions lo + 1 .. hi replaces the links end(lo) → start(lo + 1) and
    // end(hi) → start(hi + 1) by end(lo) → end(hi) and start(lo + 1) → start(hi + 1). Position −1 is home; after
    // the last path nothing follows (a link of length 0).
    std::vector<uint32_t> position(n);
    for (uint32_t i = 0; i < n; ++i) position[order[i]] = i;
    auto startId = [&](uint32_t p) { return 2 * p + reversed[p]; };
    auto endId = [&](uint32_t p) { return 2 * p + 1 - reversed[p]; };
    auto endAt = [&](int64_t i) { return i < 0 ? home : ends[endId(order[size_t(i)])]; };
    auto link = [&](glm::dvec2 a, int64_t next) {
        return next >= int64_t(n) ? 0.0 : glm::distance(a, ends[startId(order[size_t(next)])]);
    };
    auto startsAt = [&](int64_t i) { return ends[startId(order[size_t(i)])]; };
    auto gain = [&](int64_t lo, int64_t hi) {
        glm::dvec2 a = endAt(lo), b = startsAt(lo + 1), c = endAt(hi);
        double before = glm::distance(a, b) + link(c, hi + 1);
        double after = glm::distance(a, c) + link(b, hi + 1);
        return before - after;
    };
    auto travelOf = [&] {
        double sum = 0;
        for (int64_t i = -1; i + 1 < int64_t(n); ++i) sum += link(endAt(i), i + 1);
        return sum;
    };
    auto apply = [&](int64_t lo, int64_t hi) {
        std::reverse(order.begin() + lo + 1, order.begin() + hi + 1);
        for (int64_t i = lo + 1; i <= hi; ++i) {
            uint32_t p = order[size_t(i)];
            position[p] = uint32_t(i);
            reversed[p] ^= 1u;
        }
    };
    auto improve = [&] {
        // Passes until one gains less than a thousandth of the travel (later passes find little).
        for (int pass = 0; pass < kMaxPasses; ++pass) {
            bool improved = false;
            double gained = 0;
            for (int64_t i = -1; i + 1 < int64_t(n); ++i) {
                for (int side = 0; side < 2; ++side) {
                    // side 0: new link end(i) → an end nearby; side 1: new link start(i + 1) → a start nearby.
                    uint32_t from =
                        side == 0 ? (i < 0 ? UINT32_MAX : endId(order[size_t(i)])) : startId(order[size_t(i + 1)]);
                    if (from == UINT32_MAX) continue;
                    for (int k = 0; k < kNeighbours; ++k) {
                        uint32_t id = neighbours[size_t(from) * kNeighbours + size_t(k)];
                        if (id == UINT32_MAX) break;
                        uint32_t q = id >> 1;
                        int64_t j = position[q];
                        const bool circle = paths[q].circle();  // its one end is both
                        if (side == 0 && id != endId(q) && !circle) continue;
                        if (side == 1) {
                            if (id != startId(q) && !circle) continue;
                            j -= 1;
                        }
                        if (j == i) continue;
                        int64_t lo = std::min(i, j), hi = std::max(i, j);
                        const double g = gain(lo, hi);
                        if (g > 1e-9) {
                            gained += g;
                            apply(lo, hi);
                            improved = true;
                            break;
                        }
                    }
                }
            }
            if (!improved || gained < 1e-3 * travelOf()) break;
        }
        // Few paths: passes of every 2-opt move (all pairs), until none gains.
        if (n > kFullTwoOpt) return;
        for (int pass = 0; pass < 4 * kMaxPasses; ++pass) {
            bool improved = false;
            for (int64_t lo = -1; lo + 1 < int64_t(n); ++lo)
                for (int64_t hi = lo + 1; hi < int64_t(n); ++hi)
                    if (gain(lo, hi) > 1e-9) {
                        apply(lo, hi);
                        improved = true;
                    }
            if (!improved) break;
        }
    };
    improve();
    // Few paths: also improved from the order given (a tracer's order, chain after chain, can beat greedy's);
    // the shorter wins.
    if (n <= kFullTwoOpt) {
        const std::vector<uint32_t> greedyOrder = order;
        const std::vector<uint8_t> greedyReversed = reversed;
        const double greedyTravel = travelOf();
        for (uint32_t i = 0; i < n; ++i) order[i] = i, position[i] = i, reversed[i] = 0;
        improve();
        if (!(travelOf() < greedyTravel)) order = greedyOrder, reversed = greedyReversed;
    }

    // Never longer than the order given (greedy can lose on an input already in a good order).
    if (travelOf() > travel(paths, home)) return;
    std::vector<PlotPath> out;
    out.reserve(n);
    for (uint32_t p : order) {
        out.push_back(std::move(paths[p]));
        if (reversed[p]) out.back().reverse();
    }
    paths = std::move(out);
}

void mergeTouching(std::vector<PlotPath>& paths, double tolerance) {
    std::vector<PlotPath> out;
    out.reserve(paths.size());
    for (PlotPath& p : paths) {
        if (!out.empty() && !out.back().circle() && !p.circle() &&
            glm::distance(out.back().end(), p.start()) <= tolerance) {
            out.back().points.insert(out.back().points.end(), p.points.begin() + 1, p.points.end());
            continue;
        }
        out.push_back(std::move(p));
    }
    paths = std::move(out);
}

}  // namespace ink

namespace ink {

namespace {

// A hash grid of cells `cell` wide: ids by cell, looked up by key (never iterated: the results depend only on
// the input).
class HashGrid {
public:
    explicit HashGrid(double cell) : cell_(cell) {}
    glm::i64vec2 cellOf(glm::dvec2 p) const { return glm::i64vec2(glm::floor(p / cell_)); }
    void insert(glm::i64vec2 c, uint32_t id) { cells_[key(c)].push_back(id); }
    const std::vector<uint32_t>* at(glm::i64vec2 c) const {
        auto it = cells_.find(key(c));
        return it == cells_.end() ? nullptr : &it->second;
    }

private:
    static uint64_t key(glm::i64vec2 c) { return (uint64_t(c.x) << 32) ^ (uint64_t(c.y) & 0xffffffffu); }
    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, double* t = nullptr) {
    const glm::dvec2 d = b - a;
    const double len2 = glm::dot(d, d);
    const double u = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    if (t) *t = u;
    return glm::distance(p, a + d * u);
}

}  // namespace

size_t simplifyPaths(std::vector<PlotPath>& paths, double tolerance, double resolution) {
    size_t removed = 0;
    std::vector<PlotPath> out;
    out.reserve(paths.size());
    std::vector<uint8_t> keep;
    std::vector<std::pair<size_t, size_t>> stack;
    for (PlotPath& p : paths) {
        if (p.circle()) {
            out.push_back(std::move(p));
            continue;
        }
        const size_t given = p.points.size();
        std::vector<glm::dvec2> pts;
        pts.reserve(given);
        for (glm::dvec2 q : p.points)
            if (pts.empty() || glm::distance(pts.back(), q) >= resolution) pts.push_back(q);
        if (pts.size() > 2 && tolerance > 0) {
            keep.assign(pts.size(), 0);
            keep.front() = keep.back() = 1;
            stack.assign(1, {0, pts.size() - 1});
            while (!stack.empty()) {
                auto [i, j] = stack.back();
                stack.pop_back();
                double worst = -1;
                size_t at = i;
                for (size_t k = i + 1; k < j; ++k) {
                    const double d = segmentDistance(pts[k], pts[i], pts[j]);
                    if (d > worst) worst = d, at = k;
                }
                if (worst > tolerance) {
                    keep[at] = 1;
                    if (at - i > 1) stack.push_back({i, at});
                    if (j - at > 1) stack.push_back({at, j});
                }
            }
            size_t kept = 0;
            for (size_t k = 0; k < pts.size(); ++k)
                if (keep[k]) pts[kept++] = pts[k];
            pts.resize(kept);
        }
        p.points = std::move(pts);
        if (p.points.size() < 2 || p.length() < resolution) {
            removed += given;
            continue;
        }
        removed += given - p.points.size();
        out.push_back(std::move(p));
    }
    paths = std::move(out);
    return removed;
}

double dropRetraced(std::vector<PlotPath>& paths, double tolerance) {
    if (!(tolerance > 0)) return 0;
    // Kept stretches (each within one segment), found by samples at most `tolerance` apart inserted in a grid
    // of cells 2·tolerance wide: a stretch within `tolerance` of a point has a sample within 1.5·tolerance of
    // it, in the point's cell or one next to it.
    struct Piece {
        glm::dvec2 a, b;
        uint32_t path;
        double arc;  // arc length along its polyline at a
    };
    std::vector<Piece> pieces;
    HashGrid grid(2 * tolerance);
    auto insert = [&](const Piece& piece) {
        const uint32_t id = uint32_t(pieces.size());
        pieces.push_back(piece);
        const double len = glm::distance(piece.a, piece.b);
        const int steps = std::max(1, int(std::ceil(len / tolerance)));
        glm::i64vec2 last(INT64_MIN);
        for (int k = 0; k <= steps; ++k) {
            const glm::i64vec2 c = grid.cellOf(glm::mix(piece.a, piece.b, double(k) / steps));
            if (c != last) grid.insert(c, id);
            last = c;
        }
    };
    // Near parallel: within 15°. Strokes crossing at a shallow angle (hatching families where the view
    // foreshortens the surface: 45° apart on it, 20° on the page) stay within the tolerance for a few tolerances
    // at each crossing; with 30° those crossings were cut out, chopping the strokes into dashes. A crossing at
    // 15° or more stays within it for at most 2·tol / sin 15° = 7.7·tol, under the 8·tol a cut needs (below).
    const double cosParallel = std::cos(15.0 * M_PI / 180.0);
    // A path's own stretch within this many tolerances of arc length does not count as drawn before: at a cusp
    // of a contour the curve folds back along itself for a few tolerances (0.3 mm on the torus's inner contour
    // with a 0.3 mm pen), and cutting the fold there split one stroke into pieces with a gap at every cusp.
    constexpr double kFoldArc = 10.0;
    // Whether point q (at arc length s along path `path`, heading `dir`) lies on a kept stretch: within
    // `tolerance`, near parallel, and of another path or far along this one.
    auto covered = [&](glm::dvec2 q, glm::dvec2 dir, uint32_t path, double s) {
        const glm::i64vec2 c = grid.cellOf(q);
        for (int64_t y = c.y - 1; y <= c.y + 1; ++y)
            for (int64_t x = c.x - 1; x <= c.x + 1; ++x) {
                const std::vector<uint32_t>* cell = grid.at({x, y});
                if (!cell) continue;
                for (uint32_t id : *cell) {
                    const Piece& piece = pieces[id];
                    double t;
                    if (segmentDistance(q, piece.a, piece.b, &t) > tolerance) continue;
                    const glm::dvec2 d = piece.b - piece.a;
                    const double len = glm::length(d);
                    if (!(len > 0) || std::abs(glm::dot(d, dir)) < cosParallel * len) continue;
                    if (piece.path == path && std::abs(piece.arc + t * len - s) <= kFoldArc * tolerance) continue;
                    return true;
                }
            }
        return false;
    };

    double dropped = 0;
    const double step = 0.5 * tolerance;
    std::vector<PlotPath> out;
    out.reserve(paths.size());
    std::vector<uint8_t> cover;
    for (uint32_t pi = 0; pi < uint32_t(paths.size()); ++pi) {
        PlotPath& p = paths[pi];
        if (p.circle()) {
            out.push_back(std::move(p));
            continue;
        }
        // Each segment in sub-pieces at most `step` long, each covered or not (by its midpoint), against the
        // stretches kept before this segment.
        struct Sub {
            size_t segment;
            double t0, t1;
            bool covered;
        };
        std::vector<Sub> subs;
        std::vector<double> arcs(p.points.size(), 0);
        for (size_t i = 1; i < p.points.size(); ++i)
            arcs[i] = arcs[i - 1] + glm::distance(p.points[i - 1], p.points[i]);
        // Each segment's uncovered sub-pieces join the grid once it is tested (a straight segment cannot
        // cover itself); short covered runs kept below are not inserted (they lie on kept stretches anyway).
        for (size_t i = 0; i + 1 < p.points.size(); ++i) {
            const glm::dvec2 a = p.points[i], b = p.points[i + 1];
            const double len = arcs[i + 1] - arcs[i];
            if (!(len > 0)) continue;
            const glm::dvec2 dir = (b - a) / len;
            const int n = std::max(1, int(std::ceil(len / step)));
            const size_t first = subs.size();
            for (int k = 0; k < n; ++k) {
                const double t0 = double(k) / n, t1 = double(k + 1) / n, tm = 0.5 * (t0 + t1);
                subs.push_back({i, t0, t1, covered(glm::mix(a, b, tm), dir, pi, arcs[i] + tm * len)});
            }
            // The segment's uncovered runs are kept for what follows.
            for (size_t k = first; k < subs.size();) {
                if (subs[k].covered) {
                    ++k;
                    continue;
                }
                size_t e = k;
                while (e + 1 < subs.size() && !subs[e + 1].covered) ++e;
                insert({glm::mix(a, b, subs[k].t0), glm::mix(a, b, subs[e].t1), pi, arcs[i] + subs[k].t0 * len});
                k = e + 1;
            }
        }
        // Covered runs shorter than 8·tolerance (2 pen widths at the default --retrace) stay: a crossing, a
        // closed curve's joint; a retrace runs along a kept line for longer.
        bool anyCut = false;
        for (size_t k = 0; k < subs.size();) {
            if (!subs[k].covered) {
                ++k;
                continue;
            }
            size_t e = k;
            double len = 0;
            for (; e < subs.size() && subs[e].covered; ++e)
                len += (subs[e].t1 - subs[e].t0) * (arcs[subs[e].segment + 1] - arcs[subs[e].segment]);
            if (len < 8 * tolerance)
                for (size_t j = k; j < e; ++j) subs[j].covered = false;
            else
                anyCut = true;
            k = e;
        }
        if (!anyCut) {
            out.push_back(std::move(p));
            continue;
        }
        // The uncovered runs as polylines: the run's start, the original points inside it, its end.
        auto at = [&](size_t segment, double t) { return glm::mix(p.points[segment], p.points[segment + 1], t); };
        for (size_t k = 0; k < subs.size();) {
            size_t e = k;
            const bool cut = subs[k].covered;
            double len = 0;
            for (; e < subs.size() && subs[e].covered == cut; ++e)
                len += (subs[e].t1 - subs[e].t0) * (arcs[subs[e].segment + 1] - arcs[subs[e].segment]);
            // A sliver left between retraced stretches (a stroke weaving through others where the view crowds
            // them, near an outline) would be a pen lift for a dot: it goes with them.
            if (cut || len < kSliverTolerances * tolerance) {
                dropped += len;
            } else {
                PlotPath run;
                run.points.push_back(at(subs[k].segment, subs[k].t0));
                for (size_t j = k + 1; j < e; ++j)
                    if (subs[j].segment != subs[j - 1].segment) run.points.push_back(p.points[subs[j].segment]);
                run.points.push_back(at(subs[e - 1].segment, subs[e - 1].t1));
                out.push_back(std::move(run));
            }
            k = e;
        }
    }
    paths = std::move(out);
    return dropped;
}

size_t mergeEnds(std::vector<PlotPath>& paths, double tolerance, double resolution) {
    if (!(tolerance > 0)) return 0;
    const uint32_t n = uint32_t(paths.size());
    // Path end 2p is path p's start, 2p + 1 its end; circles take no part.
    HashGrid grid(tolerance);
    for (uint32_t p = 0; p < n; ++p)
        if (!paths[p].circle()) {
            grid.insert(grid.cellOf(paths[p].start()), 2 * p);
            grid.insert(grid.cellOf(paths[p].end()), 2 * p + 1);
        }
    std::vector<uint8_t> used(n, 0);
    // The nearest end of a free path within `tolerance` of q (ties: the lower id); UINT32_MAX when none.
    auto nearest = [&](glm::dvec2 q) {
        uint32_t best = UINT32_MAX;
        double bestD = tolerance;
        const glm::i64vec2 c = grid.cellOf(q);
        for (int64_t y = c.y - 1; y <= c.y + 1; ++y)
            for (int64_t x = c.x - 1; x <= c.x + 1; ++x)
                if (const std::vector<uint32_t>* cell = grid.at({x, y}))
                    for (uint32_t id : *cell) {
                        if (used[id >> 1]) continue;
                        const uint32_t p = id >> 1;
                        const double d = glm::distance(q, (id & 1u) ? paths[p].end() : paths[p].start());
                        if (d > tolerance) continue;
                        if (best == UINT32_MAX || d < bestD || (d == bestD && id < best)) bestD = d, best = id;
                    }
        return best;
    };
    size_t joins = 0;
    std::vector<PlotPath> out;
    out.reserve(paths.size());
    for (uint32_t p = 0; p < n; ++p) {
        if (used[p]) continue;
        used[p] = 1;
        PlotPath chain = std::move(paths[p]);
        if (!chain.circle()) {
            // Grown at its end, then (reversed) at what was its start; a closed polyline is left closed.
            for (int side = 0; side < 2; ++side) {
                if (side == 1) chain.reverse();
                for (;;) {
                    if (glm::distance(chain.points.front(), chain.points.back()) < resolution) break;
                    const uint32_t id = nearest(chain.points.back());
                    if (id == UINT32_MAX) break;
                    const uint32_t q = id >> 1;
                    used[q] = 1;
                    PlotPath& next = paths[q];
                    if (id & 1u) next.reverse();
                    auto from = next.points.begin();
                    if (glm::distance(chain.points.back(), *from) < resolution) ++from;
                    chain.points.insert(chain.points.end(), from, next.points.end());
                    ++joins;
                }
            }
            chain.reverse();  // back the way the first path was given
        }
        out.push_back(std::move(chain));
    }
    paths = std::move(out);
    return joins;
}

}  // namespace ink
