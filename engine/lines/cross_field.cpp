// The cross field of the hatching (cross_field.h).
#include "lines/cross_field.h"
#include "base/common.h"
#include "base/point_hash.h"
#include "base/point_tree.h"
#include "shared/cross_field.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <queue>
#include <thread>

namespace ink {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

Vector2d fourthPower(const Vector3d& u, const Vector3d& t1, const Vector3d& t2) {
    const double x = u.dot(t1), y = u.dot(t2), r2 = x * x + y * y;
    if (!(r2 > 1e-30)) return Vector2d::Zero();
    const double c = x * x / r2 - y * y / r2, s = 2 * x * y / r2;  // e^{2iθ}
    return {c * c - s * s, 2 * c * s};                             // e^{4iθ}
}

namespace {

// Runs body(begin, end) over [0, n) in one chunk per thread. Every index is written by one thread only, from what
// the previous pass left: the result does not depend on `threads`.
template <class Body>
void threadChunks(size_t n, unsigned threads, Body body) {
    size_t t = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    t = std::clamp<size_t>(std::min(t, n / 256 + 1), 1, 64);
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back(body, n * k / t, n * (k + 1) / t);
    body(size_t(0), n / t);
    for (std::thread& th : pool) th.join();
}

// A unit tangent at n: any (the same for the same n).
Vector3d anyTangent(const Vector3d& n) {
    Vector3d a = std::abs(n.x()) < 0.6 ? Vector3d::UnitX() : Vector3d::UnitY();
    return (a - a.dot(n) * n).normalized();
}

// Where the curvature gives no direction, the coarsest level starts from this (shared/cross_field.h,
// FIELD_START_CONFIDENCE): the tangent of the y axis, or of the x axis where the normal is near ±y.
Vector3d axisTangent(const Vector3d& n) {
    const Vector3d a = std::abs(n.y()) < 0.95 ? Vector3d::UnitY() : Vector3d::UnitX();
    return (a - a.dot(n) * n).normalized();
}

// The tangent direction at angle θ from t1 in the frame (t1, n × t1).
Vector3d atAngle(const Vector3d& t1, const Vector3d& n, double theta) {
    return std::cos(theta) * t1 + std::sin(theta) * n.cross(t1);
}

// Points of one level while the graph is built: positions, normals, the k nearest neighbours on the same side of
// the surface (local indices, kNone where fewer) and the distance to the nearest.
struct GraphLevel {
    std::vector<Vector3d> p, n;
    std::vector<uint32_t> neighbours, parent;    // parent: local, in the next level
    std::vector<uint32_t> childStart, children;  // local, in the previous level
    std::vector<double> nearest;
};

void findNeighbours(GraphLevel& level, uint32_t k, unsigned threads) {
    const size_t m = level.p.size();
    level.neighbours.assign(m * k, CrossFieldGraph::kNone);
    level.nearest.assign(m, 0.0);
    if (m < 2) return;
    PointCloud cloud{level.p};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    threadChunks(m, threads, [&](size_t begin, size_t end) {
        std::vector<uint32_t> index(k + 1);
        std::vector<double> squared(k + 1);
        for (size_t i = begin; i < end; ++i) {
            const size_t found = tree.knnSearch(level.p[i].data(), k + 1, index.data(), squared.data());
            uint32_t used = 0;
            bool first = true;
            for (size_t j = 0; j < found; ++j) {
                if (index[j] == i) continue;
                if (first) level.nearest[i] = std::sqrt(squared[j]), first = false;
                if (level.n[index[j]].dot(level.n[i]) > 0.0 && used < k)
                    level.neighbours[i * k + used++] = uint32_t(index[j]);
            }
        }
    });
}

// Runs body(i) for i in [begin, end) in parallel chunks.
template <class Body>
void parallelRange(uint32_t begin, uint32_t end, unsigned threads, Body body) {
    threadChunks(end - begin, threads, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) body(uint32_t(begin + i));
    });
}

}  // namespace

CrossFieldGraph buildCrossFieldGraph(const std::vector<SurfaceSample>& samples, uint32_t k, unsigned threads) {
    CrossFieldGraph graph;
    graph.k = k = std::max(1u, k);
    const size_t m = samples.size();
    std::vector<GraphLevel> levels(1);
    levels[0].p.resize(m);
    levels[0].n.resize(m);
    for (size_t i = 0; i < m; ++i) {
        levels[0].p[i] = samples[i].position;
        levels[0].n[i] = samples[i].normal.normalized();
    }
    findNeighbours(levels[0], k, threads);
    if (m > 0) {
        std::vector<double> nearest = levels[0].nearest;
        std::nth_element(nearest.begin(), nearest.begin() + long(m / 2), nearest.end());
        graph.spacing = std::max(nearest[m / 2], 1e-6);
    }
    // Coarser levels: in each cell of a grid twice as coarse as the last, the first point stands for the others.
    for (double cell = 3 * graph.spacing; levels.back().p.size() > 1500 && levels.size() < 12; cell *= 2) {
        GraphLevel& last = levels.back();
        GraphLevel up;
        std::unordered_map<uint64_t, uint32_t> index;
        std::vector<std::vector<uint32_t>> kids;
        last.parent.resize(last.p.size());
        for (size_t i = 0; i < last.p.size(); ++i) {
            const Eigen::Array3i c = (last.p[i].array() / cell).floor().cast<int>();
            const uint64_t key = cellKey(c.x(), c.y(), c.z());
            // The two sides of a thin part share cells: points facing away from the cell's first get their own.
            auto found = index.find(key);
            const uint64_t side = found != index.end() && up.n[found->second].dot(last.n[i]) < 0.0 ? 1ull << 63 : 0;
            auto [it, added] = index.emplace(key | side, uint32_t(up.p.size()));
            if (added) {
                up.p.push_back(last.p[i]);
                up.n.push_back(last.n[i]);
                kids.emplace_back();
            }
            last.parent[i] = it->second;
            kids[it->second].push_back(uint32_t(i));
        }
        if (up.p.size() > last.p.size() * 0.8) {  // no longer shrinking (scattered points)
            last.parent.clear();
            break;
        }
        up.childStart.push_back(0);
        for (const std::vector<uint32_t>& c : kids) {
            up.children.insert(up.children.end(), c.begin(), c.end());
            up.childStart.push_back(uint32_t(up.children.size()));
        }
        findNeighbours(up, k, threads);
        levels.push_back(std::move(up));
    }

    // One level after another, in global indices.
    graph.levelStart.push_back(0);
    for (const GraphLevel& level : levels)
        graph.levelStart.push_back(graph.levelStart.back() + uint32_t(level.p.size()));
    const uint32_t total = graph.points();
    graph.neighbours.assign(size_t(total) * k, CrossFieldGraph::kNone);
    graph.parent.assign(total, CrossFieldGraph::kNone);
    graph.childStart.assign(size_t(total) + 1, 0);
    for (size_t l = 0; l < levels.size(); ++l) {
        const GraphLevel& level = levels[l];
        const uint32_t at = graph.levelStart[l];
        for (size_t j = 0; j < level.neighbours.size(); ++j)
            if (level.neighbours[j] != CrossFieldGraph::kNone)
                graph.neighbours[size_t(at) * k + j] = at + level.neighbours[j];
        for (size_t i = 0; i < level.parent.size(); ++i)
            graph.parent[at + i] = graph.levelStart[l + 1] + level.parent[i];
        for (size_t i = 0; i < level.p.size(); ++i) {
            graph.childStart[at + i] = uint32_t(graph.children.size());
            if (l == 0) continue;
            for (uint32_t c = level.childStart[i]; c < level.childStart[i + 1]; ++c)
                graph.children.push_back(graph.levelStart[l - 1] + level.children[c]);
        }
    }
    graph.childStart[total] = uint32_t(graph.children.size());
    return graph;
}

CrossFieldSolution solveCrossField(const Surface& surface, const std::vector<SurfaceSample>& samples,
                                   const CrossFieldGraph& graph, const CrossFieldOptions& options) {
    const uint32_t m = uint32_t(samples.size()), total = graph.points(), k = graph.k;
    const unsigned threads = options.threads;
    std::vector<Vector3d> n(total), seed(total), d(total), next(total);
    std::vector<double> confidence(total, 0.0);
    // The seeds: principal directions of the shape operator in a tangent frame (t1, t2).
    parallelRange(0, m, threads, [&](uint32_t i) {
        Vector3d x = samples[i].position, gradient;
        Matrix3d hessian;
        surface.eval(x, gradient, &hessian);
        const double g = gradient.norm();
        Vector3d normal = g > 1e-12 && gradient.allFinite() ? Vector3d(gradient / g) : samples[i].normal.normalized();
        if (normal.dot(samples[i].normal) < 0) normal = -normal;
        const Vector3d t1 = anyTangent(normal), t2 = normal.cross(t1);
        double a = 0, b = 0, c = 0;
        if (g > 1e-12 && hessian.allFinite()) {
            a = t1.dot(hessian * t1) / g, b = t1.dot(hessian * t2) / g, c = t2.dot(hessian * t2) / g;
        }
        const double spread = std::sqrt((a - c) * (a - c) + 4 * b * b);  // |k1 − k2|
        // The direction of the eigenvalue (a + c)/2 + spread/2; the other one has the larger |k| when a + c < 0.
        const double psi = 0.5 * std::atan2(2 * b, a - c) + (a + c < 0 ? 0.5 * M_PI : 0.0);
        const double s = spread * options.featureSize;
        n[i] = normal;
        seed[i] = atAngle(t1, normal, psi);
        confidence[i] = std::isfinite(s) ? s * s / (1 + s * s) : 0.0;
    });
    // Restriction: a coarse point's seed is the confidence-weighted e^{4iψ} average of its children's, in the frame
    // of the first (whose normal it has).
    const size_t levels = graph.levels();
    for (size_t l = 1; l < levels; ++l)
        parallelRange(graph.levelStart[l], graph.levelStart[l + 1], threads, [&](uint32_t r) {
            const uint32_t first = graph.childStart[r], last = graph.childStart[r + 1];
            const uint32_t lead = graph.children[first];
            n[r] = n[lead];
            const Vector3d t1 = seed[lead], t2 = n[r].cross(t1);
            Vector2d sum = Vector2d::Zero();
            for (uint32_t c = first; c < last; ++c)
                sum += confidence[graph.children[c]] * fourthPower(seed[graph.children[c]], t1, t2);
            confidence[r] = sum.norm() / double(last - first);
            seed[r] = atAngle(t1, n[r], 0.25 * std::atan2(sum.y(), sum.x()));
        });
    // Jacobi sweeps of the e^{4iθ} average on one level (cross_field.h): each reads the previous sweep only.
    auto smooth = [&](size_t l, uint32_t sweeps) {
        for (uint32_t sweep = 0; sweep < sweeps; ++sweep) {
            parallelRange(graph.levelStart[l], graph.levelStart[l + 1], threads, [&](uint32_t i) {
                const Vector3d& normal = n[i];
                const Vector3d t1 = d[i], t2 = normal.cross(t1);
                Vector2d z(1.0, 0.0);  // itself: a damped step
                for (uint32_t j = 0; j < k; ++j) {
                    const uint32_t o = graph.neighbours[size_t(i) * k + j];
                    if (o != CrossFieldGraph::kNone) z += fourthPower(d[o], t1, t2);
                }
                z += options.fidelity * confidence[i] * fourthPower(seed[i], t1, t2);
                next[i] = z.squaredNorm() > 1e-24 ? atAngle(t1, normal, 0.25 * std::atan2(z.y(), z.x())) : t1;
            });
            d.swap(next);  // (the other levels' entries of `next` are stale: only this level's are read again)
        }
    };
    // Coarse to fine: start from the seeds, smooth, hand each point's direction down to the points it stands for.
    if (levels > 0) {
        const size_t coarsest = levels - 1;
        for (uint32_t i = graph.levelStart[coarsest]; i < graph.levelStart[coarsest + 1]; ++i)
            d[i] = confidence[i] >= gpu::FIELD_START_CONFIDENCE ? seed[i] : axisTangent(n[i]);
        smooth(coarsest, options.coarseSweeps);
        for (size_t l = coarsest; l-- > 0;) {
            parallelRange(graph.levelStart[l], graph.levelStart[l + 1], threads, [&](uint32_t i) {
                const Vector3d& up = d[graph.parent[i]];
                const Vector3d t = up - up.dot(n[i]) * n[i];
                d[i] = t.norm() > 1e-6 ? Vector3d(t.normalized()) : seed[i];
            });
            smooth(l, options.fineSweeps);
        }
    }
    CrossFieldSolution solution;
    solution.normals.assign(n.begin(), n.begin() + m);
    solution.principal.assign(seed.begin(), seed.begin() + m);
    solution.directions.assign(d.begin(), d.begin() + m);
    solution.confidence.resize(m);
    for (uint32_t i = 0; i < m; ++i) solution.confidence[i] = float(confidence[i]);
    return solution;
}

CrossField::CrossField(const Surface& surface, const std::vector<SurfaceSample>& samples,
                       const CrossFieldOptions& options) {
    const CrossFieldGraph graph = buildCrossFieldGraph(samples, options.neighbours, options.threads);
    *this = CrossField(samples, graph, solveCrossField(surface, samples, graph, options), options.featureSize);
}

CrossField::CrossField(const std::vector<SurfaceSample>& samples, const CrossFieldGraph& graph,
                       CrossFieldSolution solution, double featureSize)
    : normals_(std::move(solution.normals)),
      directions_(std::move(solution.directions)),
      principal_(std::move(solution.principal)),
      confidence_(std::move(solution.confidence)) {
    const size_t m = samples.size();
    if (normals_.size() != m || directions_.size() != m || principal_.size() != m || confidence_.size() != m ||
        graph.levelStart.size() < 2 || graph.levelStart[1] != m)
        throw Error("a cross field's solution does not match its samples");
    positions_.resize(m);
    for (size_t i = 0; i < m; ++i) positions_[i] = samples[i].position;
    if (m == 0) return;
    const uint32_t k = graph.k;

    // The comb. Where the curvature is clear (confidence ≥ kAnchorConfidence) each point picks, of its four
    // directions, the one nearest its own smaller principal curvature: a choice made from the point alone, so
    // that a device's float and the CPU's double make the same one. The rest is reached over the neighbour graph
    // from those anchors (or, in a part with none, from its most confident point), most confident first (ties by
    // index: deterministic), each point matched to the one it was reached from.
    // Flat ground (flat()): the normal's largest turn to a neighbour, per unit distance (a curvature), against
    // kFlatBend / featureSize.
    flat_.assign(m, 0);
    for (uint32_t i = 0; i < m; ++i) {
        double bend = 0;
        uint32_t measured = 0;  // a point with fewer neighbours than this says nothing of its ground
        for (uint32_t j = 0; j < k; ++j) {
            const uint32_t o = graph.neighbours[size_t(i) * k + j];
            if (o == CrossFieldGraph::kNone) continue;
            const double d = (positions_[o] - positions_[i]).norm();
            if (d > 0) bend = std::max(bend, (normals_[o] - normals_[i]).norm() / d), ++measured;
        }
        flat_[i] = measured >= 3 && bend * featureSize < kFlatBend;
    }
    combed_.assign(m, Vector3d::Zero());
    std::vector<char> reached(m, 0);
    using Item = std::pair<float, uint32_t>;
    auto lower = [](const Item& a, const Item& b) {
        return a.first < b.first || (a.first == b.first && a.second > b.second);
    };
    std::priority_queue<Item, std::vector<Item>, decltype(lower)> queue(lower);
    // Of i's four directions, the one nearest `reference` (or its own where that is along the normal).
    auto comb = [&](uint32_t i, const Vector3d& reference) {
        combed_[i] = directions_[i];
        Vector3d matched;
        if (CrossField::nearestOf(directions_[i], normals_[i], reference, matched)) combed_[i] = matched;
    };
    auto anchor = [&](uint32_t i) {  // the smaller principal curvature's direction
        reached[i] = 1;
        comb(i, normals_[i].cross(principal_[i]));
        queue.push({confidence_[i], i});
    };
    auto grow = [&] {
        while (!queue.empty()) {
            const uint32_t i = queue.top().second;
            queue.pop();
            for (uint32_t j = 0; j < k; ++j) {
                const uint32_t o = graph.neighbours[size_t(i) * k + j];
                if (o == CrossFieldGraph::kNone || reached[o]) continue;
                reached[o] = 1;
                comb(o, combed_[i]);
                queue.push({confidence_[o], o});
            }
        }
    };
    // The curved parts first, grown from their clear curvature without crossing flat ground.
    for (uint32_t i = 0; i < m; ++i) reached[i] = flat_[i];
    for (uint32_t i = 0; i < m; ++i)
        if (confidence_[i] >= kAnchorConfidence && !flat_[i]) anchor(i);
    grow();
    // Then each piece of flat ground (linked by neighbours) in one direction, its field and comb alike: the way the
    // curved points beside it are combed (their e^{2iθ} average in its mean tangent plane: a plate's long fillets
    // outweigh its short ones), or, where they agree on none (|average| < kFramed), the tangent of the fixed axis
    // the field started from. Grown from its edges instead, a flat face framed by fillets was split along its
    // diagonals.
    std::vector<char> done(m, 0);
    std::vector<uint32_t> piece;
    for (uint32_t seed = 0; seed < m; ++seed) {
        if (!flat_[seed] || done[seed]) continue;
        piece.assign(1, seed);
        done[seed] = 1;
        Vector3d normal = Vector3d::Zero();
        for (size_t q = 0; q < piece.size(); ++q) {
            const uint32_t i = piece[q];
            normal += normals_[i];
            for (uint32_t j = 0; j < k; ++j) {
                const uint32_t o = graph.neighbours[size_t(i) * k + j];
                if (o != CrossFieldGraph::kNone && flat_[o] && !done[o]) done[o] = 1, piece.push_back(o);
            }
        }
        const Vector3d t1 = anyTangent(normal.normalized()), t2 = normal.normalized().cross(t1);
        Vector2d around = Vector2d::Zero();
        double contacts = 0;
        for (const uint32_t i : piece)
            for (uint32_t j = 0; j < k; ++j) {
                const uint32_t o = graph.neighbours[size_t(i) * k + j];
                if (o == CrossFieldGraph::kNone || flat_[o] || combed_[o].isZero()) continue;
                const double x = combed_[o].dot(t1), y = combed_[o].dot(t2), r2 = x * x + y * y;
                if (r2 > 1e-12) around += Vector2d(x * x - y * y, 2 * x * y) / r2, contacts += 1;
            }
        // A square face's edges cancel: the axis rather than a direction their noise picks.
        const bool framed = around.norm() > kFramed * contacts;
        // The fixed axis chosen once for the piece, from its mean normal (chosen per point, a plane tilted about
        // 18° from y took x at some points and y at others).
        const Vector3d way = framed ? atAngle(t1, normal.normalized(), 0.5 * std::atan2(around.y(), around.x()))
                                    : axisTangent(normal.normalized());
        for (const uint32_t i : piece) {
            const Vector3d t = way - way.dot(normals_[i]) * normals_[i];
            if (t.norm() > 1e-6) directions_[i] = t.normalized();
            comb(i, way);
            queue.push({confidence_[i], i});
        }
    }
    grow();
    std::vector<uint32_t> order(m);
    for (uint32_t i = 0; i < m; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return confidence_[a] > confidence_[b]; });
    for (uint32_t root : order)
        if (!reached[root]) {
            anchor(root);
            grow();
        }

    // The lookup grid.
    radius_ = 2.5 * graph.spacing;
    inverseCell_ = 1.0 / radius_;
    for (uint32_t i = 0; i < m; ++i) {
        const Eigen::Array3i c = (positions_[i].array() * inverseCell_).floor().cast<int>();
        const uint64_t key = cellKey(c.x(), c.y(), c.z());
        cells_[key].push_back(i);
    }
}

bool CrossField::nearestOf(const Vector3d& d, const Vector3d& n, const Vector3d& reference, Vector3d& out) {
    Vector3d t1 = reference - reference.dot(n) * n;
    if (!(t1.norm() > 1e-9)) return false;
    t1.normalize();
    const Vector2d z = fourthPower(d, t1, n.cross(t1));
    if (!(z.squaredNorm() > 0)) return false;
    out = atAngle(t1, n, 0.25 * std::atan2(z.y(), z.x()));
    return true;
}

bool CrossField::lookup(const Vector3d& x, const Vector3d& n, const Vector3d& reference, Vector3d& direction,
                        double* coherence, Vector2d* flatComb) const {
    Vector3d t1 = reference - reference.dot(n) * n;
    if (!(t1.norm() > 1e-9) || cells_.empty()) return false;
    t1.normalize();
    const Vector3d t2 = n.cross(t1);
    const Eigen::Array3i c = (x.array() * inverseCell_).floor().cast<int>();
    const double r2 = radius_ * radius_;
    Vector2d z = Vector2d::Zero(), comb = Vector2d::Zero();
    double total = 0;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const Eigen::Array3i q = c + Eigen::Array3i(dx, dy, dz);
                const uint64_t key = cellKey(q.x(), q.y(), q.z());
                auto it = cells_.find(key);
                if (it == cells_.end()) continue;
                for (uint32_t j : it->second) {
                    const double d2 = (positions_[j] - x).squaredNorm();
                    if (d2 >= r2 || normals_[j].dot(n) < 0.5) continue;
                    const double w = (1 - d2 / r2) * (1 - d2 / r2);
                    z += w * fourthPower(directions_[j], t1, t2);
                    total += w;
                    if (flatComb && flat_[j]) {
                        const double cx = combed_[j].dot(t1), cy = combed_[j].dot(t2), c2 = cx * cx + cy * cy;
                        if (c2 > 0) comb += (w / c2) * Vector2d(cx * cx - cy * cy, 2 * cx * cy);
                    }
                }
            }
    if (!(total > 0)) return false;
    if (coherence) *coherence = z.norm() / total;
    if (flatComb) *flatComb = comb / total;
    direction = atAngle(t1, n, 0.25 * std::atan2(z.y(), z.x()));
    return true;
}

}  // namespace ink
