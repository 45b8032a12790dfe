// The cross field of the hatching (cross_field.h).
#include "lines/cross_field.h"
#include "base/point_hash.h"
#include "base/point_tree.h"

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
void parallelChunks(size_t n, unsigned threads, Body body) {
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

// The tangent direction at angle θ from t1 in the frame (t1, n × t1).
Vector3d atAngle(const Vector3d& t1, const Vector3d& n, double theta) {
    return std::cos(theta) * t1 + std::sin(theta) * n.cross(t1);
}

// One level of the hierarchy: points, their seeds and the current field, and the k nearest neighbours on the
// same side of the surface (UINT32_MAX where fewer).
struct Level {
    std::vector<Vector3d> p, n, seed, d;
    std::vector<double> confidence;
    std::vector<uint32_t> neighbours;  // k per point
    std::vector<uint32_t> parent;      // the point of the next coarser level standing for this one
    std::vector<double> nearest;       // distance to the nearest neighbour
};

void findNeighbours(Level& level, uint32_t k, unsigned threads) {
    const size_t m = level.p.size();
    level.neighbours.assign(m * k, UINT32_MAX);
    level.nearest.assign(m, 0.0);
    if (m < 2) return;
    PointCloud cloud{level.p};
    const PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    parallelChunks(m, threads, [&](size_t begin, size_t end) {
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

// Jacobi sweeps of the e^{4iθ} average (cross_field.h).
void smooth(Level& level, uint32_t k, uint32_t sweeps, double fidelity, unsigned threads) {
    const size_t m = level.p.size();
    std::vector<Vector3d> next(m);
    for (uint32_t sweep = 0; sweep < sweeps; ++sweep) {
        parallelChunks(m, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const Vector3d& n = level.n[i];
                const Vector3d t1 = level.d[i], t2 = n.cross(t1);
                Vector2d z(1.0, 0.0);  // itself: a damped step
                for (uint32_t j = 0; j < k; ++j) {
                    const uint32_t o = level.neighbours[i * k + j];
                    if (o != UINT32_MAX) z += fourthPower(level.d[o], t1, t2);
                }
                z += fidelity * level.confidence[i] * fourthPower(level.seed[i], t1, t2);
                next[i] = z.squaredNorm() > 1e-24 ? atAngle(t1, n, 0.25 * std::atan2(z.y(), z.x())) : t1;
            }
        });
        level.d.swap(next);
    }
}

}  // namespace

CrossField::CrossField(const Surface& surface, const std::vector<SurfaceSample>& samples,
                       const CrossFieldOptions& options) {
    const size_t m = samples.size();
    const uint32_t k = std::max(1u, options.neighbours);
    positions_.resize(m);
    normals_.resize(m);
    principal_.resize(m);
    confidence_.resize(m);
    std::vector<Level> levels(1);
    Level& fine = levels[0];
    fine.p.resize(m);
    fine.n.resize(m);
    fine.seed.resize(m);
    fine.confidence.resize(m);
    // The seeds: principal directions of the shape operator in a tangent frame (t1, t2).
    parallelChunks(m, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            Vector3d x = samples[i].position, gradient;
            Matrix3d hessian;
            surface.eval(x, gradient, &hessian);
            const double g = gradient.norm();
            Vector3d n = g > 1e-12 && gradient.allFinite() ? Vector3d(gradient / g) : samples[i].normal.normalized();
            if (n.dot(samples[i].normal) < 0) n = -n;
            const Vector3d t1 = anyTangent(n), t2 = n.cross(t1);
            double a = 0, b = 0, c = 0;
            if (g > 1e-12 && hessian.allFinite()) {
                a = t1.dot(hessian * t1) / g, b = t1.dot(hessian * t2) / g, c = t2.dot(hessian * t2) / g;
            }
            const double spread = std::sqrt((a - c) * (a - c) + 4 * b * b);  // |k1 − k2|
            // The direction of the eigenvalue (a + c)/2 + spread/2; the other one has the larger |k| when a + c < 0.
            const double psi = 0.5 * std::atan2(2 * b, a - c) + (a + c < 0 ? 0.5 * M_PI : 0.0);
            const double s = spread * options.featureSize;
            positions_[i] = fine.p[i] = x;
            normals_[i] = fine.n[i] = n;
            principal_[i] = fine.seed[i] = atAngle(t1, n, psi);
            confidence_[i] = float(fine.confidence[i] = std::isfinite(s) ? s * s / (1 + s * s) : 0.0);
        }
    });
    if (m == 0) return;
    findNeighbours(fine, k, options.threads);
    std::vector<double> nearest = fine.nearest;
    std::nth_element(nearest.begin(), nearest.begin() + long(m / 2), nearest.end());
    const double spacing = std::max(nearest[m / 2], 1e-6);

    // Coarser levels: in each cell of a grid twice as coarse as the last, the first point stands for the others,
    // its seed their confidence-weighted e^{4iψ} average.
    for (double cell = 3 * spacing; levels.back().p.size() > 1500 && levels.size() < 12; cell *= 2) {
        Level& last = levels.back();
        Level up;
        std::unordered_map<uint64_t, uint32_t> index;
        std::vector<Vector2d> sum;
        std::vector<double> count;
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
                up.seed.push_back(last.seed[i]);
                sum.push_back(Vector2d::Zero());
                count.push_back(0);
            }
            const uint32_t r = it->second;
            last.parent[i] = r;
            sum[r] += last.confidence[i] * fourthPower(last.seed[i], up.seed[r], up.n[r].cross(up.seed[r]));
            count[r] += 1;
        }
        if (up.p.size() > last.p.size() * 0.8) break;  // no longer shrinking (scattered points)
        up.confidence.resize(up.p.size());
        for (size_t r = 0; r < up.p.size(); ++r) {
            up.confidence[r] = sum[r].norm() / count[r];
            up.seed[r] = atAngle(up.seed[r], up.n[r], 0.25 * std::atan2(sum[r].y(), sum[r].x()));
        }
        findNeighbours(up, k, options.threads);
        levels.push_back(std::move(up));
    }

    // Coarse to fine: start from the seeds, smooth, hand each point's direction down to the points it stands for.
    Level& coarsest = levels.back();
    coarsest.d = coarsest.seed;
    smooth(coarsest, k, options.coarseSweeps, options.fidelity, options.threads);
    for (size_t l = levels.size() - 1; l-- > 0;) {
        Level& level = levels[l];
        const Level& up = levels[l + 1];
        level.d.resize(level.p.size());
        for (size_t i = 0; i < level.p.size(); ++i) {
            const Vector3d& d = up.d[level.parent[i]];
            const Vector3d t = d - d.dot(level.n[i]) * level.n[i];
            level.d[i] = t.norm() > 1e-6 ? Vector3d(t.normalized()) : level.seed[i];
        }
        smooth(level, k, options.fineSweeps, options.fidelity, options.threads);
    }
    directions_ = std::move(levels[0].d);

    // The comb: a maximum-confidence spanning forest of the neighbour graph, grown by a priority queue (ties by
    // index: deterministic).
    const std::vector<uint32_t>& graph = levels[0].neighbours;  // (`fine` moved when levels grew)
    combed_.assign(m, Vector3d::Zero());
    std::vector<uint32_t> order(m);
    for (uint32_t i = 0; i < m; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return confidence_[a] > confidence_[b]; });
    std::vector<char> reached(m, 0);
    using Item = std::pair<float, uint32_t>;
    auto lower = [](const Item& a, const Item& b) {
        return a.first < b.first || (a.first == b.first && a.second > b.second);
    };
    std::priority_queue<Item, std::vector<Item>, decltype(lower)> queue(lower);
    for (uint32_t root : order) {
        if (reached[root]) continue;
        reached[root] = 1;
        combed_[root] = normals_[root].cross(principal_[root]);  // the smaller principal curvature's direction
        Vector3d matched;
        if (CrossField::nearestOf(directions_[root], normals_[root], combed_[root], matched)) combed_[root] = matched;
        queue.push({confidence_[root], root});
        while (!queue.empty()) {
            const uint32_t i = queue.top().second;
            queue.pop();
            for (uint32_t j = 0; j < k; ++j) {
                const uint32_t o = graph[size_t(i) * k + j];
                if (o == UINT32_MAX || reached[o]) continue;
                reached[o] = 1;
                combed_[o] = directions_[o];
                if (CrossField::nearestOf(directions_[o], normals_[o], combed_[i], matched)) combed_[o] = matched;
                queue.push({confidence_[o], o});
            }
        }
    }

    // The lookup grid.
    radius_ = 2.5 * spacing;
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
                        double* coherence) const {
    Vector3d t1 = reference - reference.dot(n) * n;
    if (!(t1.norm() > 1e-9) || cells_.empty()) return false;
    t1.normalize();
    const Vector3d t2 = n.cross(t1);
    const Eigen::Array3i c = (x.array() * inverseCell_).floor().cast<int>();
    const double r2 = radius_ * radius_;
    Vector2d z = Vector2d::Zero();
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
                }
            }
    if (!(total > 0)) return false;
    if (coherence) *coherence = z.norm() / total;
    direction = atAngle(t1, n, 0.25 * std::atan2(z.y(), z.x()));
    return true;
}

}  // namespace ink
