#include "surface/pu_hrbf.h"

#include "base/common.h"
#include "base/parallel.h"
#include "surface/clean.h"
#include "surface/r3_term.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>

// OpenBLAS, when it is the LAPACK linked, splits a large solve over its own threads, which wait for each other by
// spinning: on a busy machine the far field's 1028² solve then took 13 s instead of 0.05 s. The patches are
// solved in parallel already, so OpenBLAS gets one thread during the fit. Weak: another LAPACK leaves these null.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));
extern "C" int openblas_get_num_threads() __attribute__((weak));

namespace ink {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

// ---- Evaluation, shared by the double model and its float twin

template <class T>
using Vec = Eigen::Matrix<T, 3, 1>;
template <class T>
using Mat = Eigen::Matrix<T, 3, 3>;

// The PU blend's sums and their derivatives: S = Σ w_i, N = Σ w_i f_i (PU blend); then F = N / S with
// ∇F = (∇N − F ∇S) / S and HF = (HN − ∇F ∇Sᵀ − ∇S ∇Fᵀ − F HS) / S.
template <class T>
struct Blend {
    bool hessian;
    T S = 0, N = 0;
    Vec<T> dS = Vec<T>::Zero(), dN = Vec<T>::Zero();
    Mat<T> HS = Mat<T>::Zero(), HN = Mat<T>::Zero();

    // Patch i at q = (x − c_i) / R_i with ‖q‖ < 1: its Wendland weight and derivatives in x.
    // W(d) = (1 − d)⁴ (4d + 1), ∇w = −20 (1 − d)³ q / R, Hw = −20/R² [(1 − d)³ I − 3 (1 − d)² q qᵀ / d].
    void addPatch(const Vec<T>& q, T radius, T f, const Vec<T>& g, const Mat<T>& H) {
        T d = q.norm(), e = T(1) - d, e2 = e * e, e3 = e2 * e;
        T w = e2 * e2 * (T(4) * d + T(1));
        Vec<T> dw = (T(-20) * e3 / radius) * q;
        T fi = radius * f;  // f_i = R h_i(q); ∇f_i = ∇h_i(q); Hf_i = Hh_i(q) / R
        S += w;
        N += w * fi;
        dS += dw;
        dN += fi * dw + w * g;
        if (hessian) {
            Mat<T> Hw = Mat<T>::Identity() * e3;
            if (d > T(0)) Hw -= (T(3) * e2 / d) * (q * q.transpose());
            Hw *= T(-20) / (radius * radius);
            HS += Hw;
            HN += fi * Hw + dw * g.transpose() + g * dw.transpose() + (w / radius) * H;
        }
    }

    // Adds the far field where the patches' weights fade (w_c = τ (1 − S/τ)³ for S < τ) and divides.
    template <class Coarse>
    T finish(T tau, Coarse coarse, Vec<T>& gradient, Mat<T>* H) {
        if (S < tau) {
            T s = S / tau, e = T(1) - s;
            T wc = tau * e * e * e;
            Vec<T> dwc = T(-3) * e * e * dS;
            Mat<T> Hwc = (T(6) * e / tau) * (dS * dS.transpose()) - T(3) * e * e * HS;
            Vec<T> gc = Vec<T>::Zero();
            Mat<T> Hc = Mat<T>::Zero();
            T fc = coarse(gc, hessian ? &Hc : nullptr);
            S += wc;
            N += wc * fc;
            dN += fc * dwc + wc * gc;
            if (hessian) {
                HN += fc * Hwc + dwc * gc.transpose() + gc * dwc.transpose() + wc * Hc;
                HS += Hwc;
            }
            dS += dwc;
        }
        T F = N / S;
        gradient = (dN - F * dS) / S;
        if (H) *H = (HN - gradient * dS.transpose() - dS * gradient.transpose() - F * HS) / S;
        return F;
    }
};

// ---- The fit: an octree of cells, a patch for each cell with points

struct Octree {
    struct Node {
        Vector3d center;
        double half;
        uint32_t begin, end;  // into order
        int32_t child = -1;   // first of 8 consecutive children, or −1 for a leaf
        int depth = 0;
    };
    const std::vector<Vector3d>& points;
    std::vector<uint32_t> order;
    std::vector<Node> nodes;

    explicit Octree(const std::vector<Vector3d>& p) : points(p), order(p.size()) {
        for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        Vector3d lo = p[0], hi = p[0];
        for (const Vector3d& x : p) {
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
        }
        nodes.push_back({0.5 * (lo + hi), 0.5 * (hi - lo).maxCoeff() * (1 + 1e-9) + 1e-12, 0, uint32_t(p.size())});
    }

    // The node's points regrouped by octant, each octant's in their order (a stable counting sort through
    // `scratch`: no allocation a split; a scan's 10⁶ points split some 250,000 times).
    void split(size_t n) {
        Node node = nodes[n];
        auto octantOf = [&](uint32_t i) {
            const Vector3d& x = points[i];
            return (x.x() >= node.center.x()) | (x.y() >= node.center.y()) << 1 | (x.z() >= node.center.z()) << 2;
        };
        std::array<uint32_t, 9> start{};
        scratch.resize(node.end - node.begin);
        for (uint32_t k = node.begin; k < node.end; ++k) {
            scratch[k - node.begin] = uint8_t(octantOf(order[k]));
            ++start[size_t(scratch[k - node.begin]) + 1];
        }
        for (size_t o = 0; o < 8; ++o) start[o + 1] += start[o];
        moved.resize(node.end - node.begin);
        std::array<uint32_t, 9> at = start;
        for (uint32_t k = node.begin; k < node.end; ++k) moved[at[scratch[k - node.begin]]++] = order[k];
        std::copy(moved.begin(), moved.end(), order.begin() + node.begin);
        nodes[n].child = int32_t(nodes.size());
        for (int o = 0; o < 8; ++o) {
            Vector3d offset((o & 1) ? 1 : -1, (o & 2) ? 1 : -1, (o & 4) ? 1 : -1);
            nodes.push_back({node.center + 0.5 * node.half * offset, 0.5 * node.half, node.begin + start[size_t(o)],
                             node.begin + start[size_t(o) + 1], -1, node.depth + 1});
        }
    }
    std::vector<uint8_t> scratch;  // split's octants
    std::vector<uint32_t> moved;   // and its regrouped points

    // Indices of the points within distance < radius of x.
    void ball(const Vector3d& x, double radius, std::vector<uint32_t>& out) const {
        out.clear();
        const double r2 = radius * radius;
        std::vector<uint32_t> stack{0};
        while (!stack.empty()) {
            const Node& node = nodes[stack.back()];
            stack.pop_back();
            if (node.begin == node.end) continue;
            Vector3d gap = ((x - node.center).cwiseAbs().array() - node.half).max(0.0).matrix();
            if (gap.squaredNorm() >= r2) continue;
            if (node.child < 0) {
                for (uint32_t k = node.begin; k < node.end; ++k)
                    if ((points[order[k]] - x).squaredNorm() < r2) out.push_back(order[k]);
            } else {
                for (int o = 0; o < 8; ++o) stack.push_back(uint32_t(node.child + o));
            }
        }
        std::sort(out.begin(), out.end());  // the same nodes in the same order, whatever the tree's shape
    }
};

double wendland(double d) {
    double e = 1 - d;
    return e * e * e * e * (4 * d + 1);
}

}  // namespace

PuGrid buildPuGrid(const std::vector<PuPatch>& patches) {
    PuGrid grid;
    Vector3d lo = Vector3d::Constant(INFINITY), hi = -lo;
    std::vector<double> radii;
    for (const PuPatch& p : patches) {
        lo = lo.cwiseMin(p.center - Vector3d::Constant(p.radius));
        hi = hi.cwiseMax(p.center + Vector3d::Constant(p.radius));
        radii.push_back(p.radius);
    }
    std::nth_element(radii.begin(), radii.begin() + std::ptrdiff_t(radii.size() / 2), radii.end());
    // Cells of half the median support radius: a query's cell then lists few patches whose ball misses it (the
    // median radius measured 17% slower refining bunny-684 on lavapipe). At most 2^21 cells.
    double cell = std::max(radii[radii.size() / 2] / 2, 1e-9);
    Vector3d extent = hi - lo;
    // The entries, counted in 64 bits (the cells of each patch's bounding cube, at least those it meets), at
    // most 1024 a patch and 2^26 in all: a loaded file's few large patches over a fine grid made 4.4e9, which
    // wrapped in 32 bits. Cells only speed the look-up up; larger ones find the same patches.
    const uint64_t maxEntries =
        std::min<uint64_t>(uint64_t(1) << 26, std::max<uint64_t>(uint64_t(1) << 20, 1024 * uint64_t(patches.size())));
    auto boxEntries = [&](double c) {
        uint64_t total = 0;
        for (const PuPatch& p : patches) {
            double n = 1;
            for (int k = 0; k < 3; ++k)
                n *= std::min(std::floor((p.center[k] + p.radius - lo[k]) / c) -
                                  std::floor((p.center[k] - p.radius - lo[k]) / c) + 1,
                              std::max(std::ceil(extent[k] / c), 1.0));
            total += uint64_t(n);
        }
        return total;
    };
    while ((extent / cell).array().ceil().prod() > double(1 << 21) || boxEntries(cell) > maxEntries) cell *= 1.25;
    grid.origin = lo;
    grid.cell = cell;
    grid.dims = (extent / cell).array().ceil().cast<int>().max(1).matrix();
    const size_t cells = size_t(grid.dims.x()) * size_t(grid.dims.y()) * size_t(grid.dims.z());
    std::vector<uint32_t> count(cells + 1, 0);
    auto forCells = [&](const PuPatch& p, auto&& visit) {
        Eigen::Vector3i a = ((p.center.array() - p.radius - lo.array()) / cell).floor().cast<int>().max(0).matrix();
        Eigen::Vector3i b = ((p.center.array() + p.radius - lo.array()) / cell)
                                .floor()
                                .cast<int>()
                                .min((grid.dims.array() - 1))
                                .matrix();
        for (int z = a.z(); z <= b.z(); ++z)
            for (int y = a.y(); y <= b.y(); ++y)
                for (int x = a.x(); x <= b.x(); ++x) {
                    Vector3d cmin = lo + cell * Vector3d(x, y, z);
                    Vector3d gap = (cmin - p.center).cwiseMax(p.center - cmin - Vector3d::Constant(cell)).cwiseMax(0.0);
                    if (gap.squaredNorm() < p.radius * p.radius)
                        visit(size_t(x) + size_t(grid.dims.x()) * (size_t(y) + size_t(grid.dims.y()) * size_t(z)));
                }
    };
    // On all threads (a scan's 475,000 patches took 0.6 s on one of 16 cores): counted and filled with atomic
    // cursors, then each cell's patches sorted, so that they come in patch order as from one thread (the blend's
    // float sums follow that order).
    const size_t n = patches.size();
    parallelChunks(n, 4096, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i)
            forCells(patches[i], [&](size_t c) { std::atomic_ref<uint32_t>(count[c + 1]).fetch_add(1); });
    });
    for (size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    grid.cellStart = count;
    grid.cellPatches.resize(count[cells]);
    parallelChunks(n, 4096, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i)
            forCells(patches[i], [&](size_t c) {
                grid.cellPatches[std::atomic_ref<uint32_t>(count[c]).fetch_add(1)] = uint32_t(i);
            });
    });
    parallelChunks(cells, 1 << 14, [&](size_t begin, size_t end, size_t) {
        for (size_t c = begin; c < end; ++c)
            std::sort(grid.cellPatches.begin() + grid.cellStart[c], grid.cellPatches.begin() + grid.cellStart[c + 1]);
    });
    return grid;
}

int64_t PuGrid::cellOf(const Vector3d& x) const {
    Vector3d u = (x - origin) / cell;
    if (!(u.minCoeff() >= 0) || !(u.x() < dims.x() && u.y() < dims.y() && u.z() < dims.z())) return -1;
    Eigen::Vector3i i = u.cast<int>();
    return int64_t(i.x()) + int64_t(dims.x()) * (int64_t(i.y()) + int64_t(dims.y()) * int64_t(i.z()));
}

double PuHrbf::eval(const Vector3d& x, Vector3d& gradient, Matrix3d* hessian) const {
    Blend<double> blend{hessian != nullptr};
    int64_t cell = grid.cellOf(x);
    if (cell >= 0)
        for (uint32_t k = grid.cellStart[size_t(cell)]; k < grid.cellStart[size_t(cell) + 1]; ++k) {
            const PuPatch& patch = patches[grid.cellPatches[k]];
            Vector3d q = (x - patch.center) / patch.radius;
            if (!(q.squaredNorm() < 1)) continue;
            double f = patch.a.dot(q) + patch.b;
            Vector3d g = patch.a;
            Matrix3d H = Matrix3d::Zero();
            for (uint32_t j = patch.first; j < patch.first + patch.count; ++j)
                addR3Node<double>(q, nodes[j].p, nodes[j].alpha, nodes[j].beta, f, g, hessian ? &H : nullptr);
            blend.addPatch(q, patch.radius, f, g, H);
        }
    auto far = [&](Vector3d& g, Matrix3d* H) { return coarse.eval(x, g, H); };
    return blend.finish(tau, far, gradient, hessian);
}

double PuHrbf::patchWeight(const Vector3d& x) const {
    double S = 0;
    const int64_t cell = grid.cellOf(x);
    if (cell >= 0)
        for (uint32_t k = grid.cellStart[size_t(cell)]; k < grid.cellStart[size_t(cell) + 1]; ++k) {
            const PuPatch& patch = patches[grid.cellPatches[k]];
            const double d = (x - patch.center).norm() / patch.radius;
            if (d < 1) S += wendland(d);
        }
    return S;
}

namespace {

// The largest |eigenvalue| of P A P on the tangent plane of unit n (A symmetric).
double tangentNorm(const Matrix3d& A, const Vector3d& n) {
    const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    const double a = u.dot(A * u), b = u.dot(A * v), c = v.dot(A * v);
    return std::abs(0.5 * (a + c)) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
}

// The value of rank ⌊q·n⌋ (the fidelity's percentile ranks ⌊q·(n − 1)⌋).
double rankPercentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

}  // namespace

PuSeams measureSeams(const PuHrbf& model, size_t maxSamples) {
    PuSeams out;
    std::vector<double> tilt, ratio, rough;
    const size_t stride = std::max<size_t>(1, model.patches.size() / std::max<size_t>(1, maxSamples));
    // Each sampled patch's three figures in its own slot (the fourth is 1 where it gave them), on all threads,
    // then gathered in patch order.
    const size_t sampled = (model.patches.size() + stride - 1) / stride;
    std::vector<std::array<double, 4>> figures(sampled, {0, 0, 0, 0});
    parallelChunks(sampled, 64, [&](size_t begin, size_t end, size_t) {
        for (size_t si = begin; si < end; ++si) {
            const size_t pi = si * stride;
            const PuPatch& patch = model.patches[pi];
            if (patch.count < 2) continue;
            // Halfway from the patch's first node to its nearest neighbour in the patch, projected onto F = 0.
            const Vector3d p0 = model.nodes[patch.first].p;
            Vector3d nearest = model.nodes[patch.first + 1].p;
            for (uint32_t j = patch.first + 1; j < patch.first + patch.count; ++j)
                if ((model.nodes[j].p - p0).squaredNorm() < (nearest - p0).squaredNorm()) nearest = model.nodes[j].p;
            Vector3d x = patch.center + patch.radius * 0.5 * (p0 + nearest), gradient;
            bool onSurface = false;
            for (int k = 0; k < 8 && !onSurface; ++k) {
                const double f = model.eval(x, gradient), g2 = gradient.squaredNorm();
                if (!(g2 > 0) || !std::isfinite(f)) break;
                x -= (f / g2) * gradient;
                onSurface = std::abs(f) < 1e-10 * std::sqrt(g2);
            }
            if (!onSurface) continue;
            // The blend at x, whole, and the patches' own part of it.
            Matrix3d hessian;
            model.eval(x, gradient, &hessian);
            double S = 0;
            Vector3d ownGradient = Vector3d::Zero();
            Matrix3d ownHessian = Matrix3d::Zero();
            const int64_t cell = model.grid.cellOf(x);
            if (cell < 0) continue;
            for (uint32_t k = model.grid.cellStart[size_t(cell)]; k < model.grid.cellStart[size_t(cell) + 1]; ++k) {
                const PuPatch& other = model.patches[model.grid.cellPatches[k]];
                const Vector3d q = (x - other.center) / other.radius;
                if (!(q.squaredNorm() < 1)) continue;
                double f = other.a.dot(q) + other.b;
                Vector3d g = other.a;
                Matrix3d H = Matrix3d::Zero();
                for (uint32_t j = other.first; j < other.first + other.count; ++j)
                    addR3Node<double>(q, model.nodes[j].p, model.nodes[j].alpha, model.nodes[j].beta, f, g, &H);
                const double w = wendland(q.norm());
                S += w;
                ownGradient += w * g;
                ownHessian += (w / other.radius) * H;
            }
            if (!(S >= model.tau)) continue;  // the far field blends in here: not a seam between patches
            ownGradient /= S;
            ownHessian /= S;
            const double gn = gradient.norm();
            const Vector3d n = gradient / gn;
            figures[si][0] = std::atan2(gradient.cross(ownGradient).norm(), gradient.dot(ownGradient)) * 180.0 / M_PI;
            const double own = tangentNorm(ownHessian, n) / gn, seam = tangentNorm(hessian - ownHessian, n) / gn;
            figures[si][1] = seam / std::max(own, 1e-3);
            // The roughness: F's shape operator halfway against the mean of its two ends'.
            auto shape = [&](const Vector3d& at) {
                Vector3d g;
                Matrix3d H;
                model.eval(at, g, &H);
                return Matrix3d(H / g.norm());
            };
            const Matrix3d ends =
                0.5 * (shape(patch.center + patch.radius * p0) + shape(patch.center + patch.radius * nearest));
            const Matrix3d mid = hessian / gn;
            figures[si][2] = tangentNorm(mid - ends, n) / (0.5 * (tangentNorm(mid, n) + tangentNorm(ends, n)) + 1.0);
            figures[si][3] = 1;
        }
    });
    for (const auto& [t, r, g, given] : figures)
        if (given == 1) tilt.push_back(t), ratio.push_back(r), rough.push_back(g);
    out.samples = tilt.size();
    out.normalDegMedian = rankPercentile(tilt, 0.5);
    out.normalDegP95 = rankPercentile(tilt, 0.95);
    out.curvatureRatioMedian = rankPercentile(ratio, 0.5);
    out.curvatureRatioP95 = rankPercentile(ratio, 0.95);
    out.roughnessMedian = rankPercentile(rough, 0.5);
    out.roughnessP95 = rankPercentile(rough, 0.95);
    return out;
}

PuHrbf fitPuHrbf(const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals, const PuOptions& options,
                 PuStats* stats, PhaseTimes* phases) {
    const size_t n = points.size();
    auto lap = [phases](const char* name) {
        if (phases) phases->lap(name);
    };
    if (n < 2) throw Error("too few distinct points to fit a surface: need at least 2, got " + std::to_string(n));
    if (normals.size() != n)
        throw Error("cannot fit: " + std::to_string(n) + " points but " + std::to_string(normals.size()) + " normals");
    struct OneBlasThread {
        int previous = openblas_get_num_threads ? openblas_get_num_threads() : 0;
        OneBlasThread() {
            if (openblas_set_num_threads) openblas_set_num_threads(1);
        }
        ~OneBlasThread() {
            if (openblas_set_num_threads && previous > 0) openblas_set_num_threads(previous);
        }
    } oneBlasThread;
    for (size_t i = 0; i < n; ++i)
        if (!points[i].allFinite() || !normals[i].allFinite() || normals[i].squaredNorm() == 0)
            throw Error("cannot fit: point " + std::to_string(i) + " has a NaN, infinite or zero coordinate or normal");

    // The far field: a global HRBF on well-spread points, fewer if that system is too ill-conditioned; solved on
    // a thread of its own beside the patches (its one dense system of 4 × 256 + 4 unknowns took longer than all
    // the bunny-684's patches on 16 cores).
    PuHrbf model;
    std::exception_ptr farError;
    double farMs = 0;
    std::thread farField([&] {
        const auto start = std::chrono::steady_clock::now();
        try {
            std::vector<Vector3d> cp, cn;
            const size_t wanted = n > options.largeFit ? options.coarsePointsLarge : options.coarsePoints;
            for (size_t count = std::min(wanted, n);; count /= 2) {
                cp.clear();
                cn.clear();
                for (size_t i : farthestPointSample(points, count)) {
                    cp.push_back(points[i]);
                    cn.push_back(normals[i]);
                }
                try {
                    model.coarse = fitHrbf(cp, cn);
                    break;
                } catch (const Error&) {
                    if (count <= 8) throw;
                }
            }
        } catch (...) {
            farError = std::current_exception();
        }
        farMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    });
    // Joined on every way out, a throw included.
    struct Join {
        std::thread& t;
        ~Join() {
            if (t.joinable()) t.join();
        }
    } joinFarField{farField};

    // Cells: split while a cell holds more than leafPoints, or its support more than maxPatch points.
    Octree tree(points);
    for (size_t k = 0; k < tree.nodes.size(); ++k)
        if (tree.nodes[k].end - tree.nodes[k].begin > options.leafPoints && tree.nodes[k].depth < 24) tree.split(k);
    struct Support {
        Vector3d center;
        double radius;
        std::vector<uint32_t> points;
    };
    std::vector<Support> supports;
    const size_t minPatch = std::min(options.minPatch, n);
    // In rounds: the leaves' balls on all threads (the tree is only read), then, in node order, the leaves whose
    // support holds too many points split (their children are the next round's) and the others become patches.
    // The same supports in the same order as one pass over the nodes: children always came after every node
    // before them, and a ball's points are sorted whatever the tree's shape.
    for (size_t from = 0; from < tree.nodes.size();) {
        const size_t to = tree.nodes.size();
        std::vector<Support> round(to - from);
        std::vector<char> split(to - from, 0);
        parallelChunks(to - from, 256, [&](size_t begin, size_t end, size_t) {
            for (size_t r = begin; r < end; ++r) {
                const Octree::Node& node = tree.nodes[from + r];
                if (node.child >= 0 || node.begin == node.end) continue;
                double radius = options.overlap * node.half * std::sqrt(3.0);
                std::vector<uint32_t> found;
                tree.ball(node.center, radius, found);
                if (found.size() > options.maxPatch && node.depth < 24) {
                    split[r] = 1;
                    continue;
                }
                // A leaf of few points grows its ball to minPatch points; where a step of 1.25 would take in more than
                // kMaxPatchNodes (a few isolated points beside a dense region: one of CGAL's poste_france.xyz patches
                // took 3,905 points, a 115 s solve and a model no .hrbf holds), the radius is bisected back.
                double inside = radius;
                while (found.size() < minPatch) {
                    inside = radius;
                    radius *= 1.25;
                    tree.ball(node.center, radius, found);
                }
                for (double outside = radius; found.size() > kMaxPatchNodes && outside > inside * (1 + 1e-9);) {
                    radius = 0.5 * (inside + outside);
                    tree.ball(node.center, radius, found);
                    if (found.size() < minPatch) inside = radius;
                    if (found.size() > kMaxPatchNodes) outside = radius;
                    if (found.size() < minPatch) {  // bisect on from the larger, never below minPatch at the end
                        radius = outside;
                        tree.ball(node.center, radius, found);
                    }
                }
                round[r] = {node.center, radius, std::move(found)};
            }
        });
        for (size_t r = 0; r < to - from; ++r) {
            if (split[r])
                tree.split(from + r);
            else if (!round[r].points.empty())
                supports.push_back(std::move(round[r]));
        }
        from = to;
    }

    lap("supports");
    model.patches.resize(supports.size());
    std::vector<std::vector<PuNode>> local(supports.size());
    std::vector<double> residuals(supports.size(), 0);
    std::atomic<size_t> next{0}, done{0};
    std::atomic<bool> failed{false};
    std::mutex errorLock;
    std::string error;
    auto work = [&](Progress* progress) {
        std::vector<Vector3d> q, nq;
        for (size_t i; !failed && (i = next++) < supports.size();) {
            const Support& s = supports[i];
            q.clear();
            nq.clear();
            for (uint32_t j : s.points) {
                q.push_back((points[j] - s.center) / s.radius);
                nq.push_back(normals[j]);
            }
            try {
                FitStats fs;
                Hrbf h = fitHrbf(q, nq, &fs);
                PuPatch& patch = model.patches[i];
                patch.center = s.center;
                patch.radius = s.radius;
                patch.count = uint32_t(q.size());
                patch.a = h.a;
                patch.b = h.b;
                local[i].resize(q.size());
                for (size_t j = 0; j < q.size(); ++j) local[i][j] = {q[j], h.alpha[j], h.beta[j]};
                residuals[i] = fs.relativeResidual;
            } catch (const Error& e) {
                std::lock_guard<std::mutex> lock(errorLock);
                if (!failed.exchange(true)) {
                    char where[96];
                    std::snprintf(where, sizeof where, "patch %zu of %zu (at %.4g %.4g %.4g, %zu points): ", i,
                                  supports.size(), s.center.x(), s.center.y(), s.center.z(), q.size());
                    error = where + std::string(e.what());
                }
            }
            ++done;
            if (progress) progress->update(done);
        }
    };
    {
        Progress progress("fit", supports.size());
        unsigned threads = workerThreads();
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, nullptr);
        work(&progress);
        for (auto& th : pool) th.join();
    }
    if (failed) throw Error(error);
    lap("solve");
    // The nodes in patch order, copied on all threads.
    size_t nodes = 0;
    for (size_t i = 0; i < supports.size(); ++i) {
        model.patches[i].first = uint32_t(nodes);
        nodes += local[i].size();
    }
    model.nodes.resize(nodes);
    parallelChunks(supports.size(), 4096, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            std::copy(local[i].begin(), local[i].end(), model.nodes.begin() + model.patches[i].first);
            std::vector<PuNode>().swap(local[i]);
        }
    });
    lap("nodes");
    model.grid = buildPuGrid(model.patches);
    lap("grid");

    farField.join();
    if (farError) std::rethrow_exception(farError);
    if (phases) phases->add("far_field", farMs);
    // Below the weight each point gets from its own cell's patch, W(1/overlap): the far field is 0 at the data.
    model.tau = 0.9 * wendland(1.0 / options.overlap);
    lap("far_field_wait");

    if (stats) {
        stats->patches = model.patches.size();
        stats->minPatch = SIZE_MAX;
        stats->maxPatch = 0;
        for (const PuPatch& p : model.patches) {
            stats->minPatch = std::min<size_t>(stats->minPatch, p.count);
            stats->maxPatch = std::max<size_t>(stats->maxPatch, p.count);
        }
        stats->meanPatch = double(model.nodes.size()) / double(model.patches.size());
        stats->maxRelativeResidual = *std::max_element(residuals.begin(), residuals.end());
        stats->coarsePoints = model.coarse.size();
        stats->gridCells = model.grid.cellStart.size() - 1;
        stats->gridEntries = model.grid.cellPatches.size();
    }
    return model;
}

// ---- The float twin

PuFloat::PuFloat(const PuHrbf& model)
    : origin_(model.grid.origin.cast<float>()),
      invCell_(float(1.0 / model.grid.cell)),
      tau_(float(model.tau)),
      dims_(model.grid.dims),
      cellStart_(&model.grid.cellStart),
      cellPatches_(&model.grid.cellPatches) {
    size_t nodes = 0;
    for (const PuPatch& p : model.patches) nodes += (p.count + 3) / 4 * 4;
    for (auto* v : {&px_, &py_, &pz_, &alpha_, &bx_, &by_, &bz_}) v->reserve(nodes);
    patches_.reserve(model.patches.size());
    for (const PuPatch& p : model.patches) {
        Patch q{float(p.center.x()), float(p.center.y()), float(p.center.z()), float(p.radius),      float(p.a.x()),
                float(p.a.y()),      float(p.a.z()),      float(p.b),          uint32_t(px_.size()), p.count};
        for (uint32_t j = p.first; j < p.first + p.count; ++j) {
            const PuNode& node = model.nodes[j];
            px_.push_back(float(node.p.x())), py_.push_back(float(node.p.y())), pz_.push_back(float(node.p.z()));
            alpha_.push_back(float(node.alpha));
            bx_.push_back(float(node.beta.x())), by_.push_back(float(node.beta.y())),
                bz_.push_back(float(node.beta.z()));
        }
        while (px_.size() % 4) {  // zero nodes (α = β = 0) add nothing
            for (auto* v : {&px_, &py_, &pz_, &alpha_, &bx_, &by_, &bz_}) v->push_back(0.0f);
        }
        patches_.push_back(q);
    }
    const Hrbf& c = model.coarse;
    for (size_t j = 0; j < c.size(); ++j) {
        coarse_.insert(coarse_.end(),
                       {float(c.centers[j].x()), float(c.centers[j].y()), float(c.centers[j].z()), float(c.alpha[j]),
                        float(c.beta[j].x()), float(c.beta[j].y()), float(c.beta[j].z()), 0.0f});
    }
    coarseA_[0] = float(c.a.x()), coarseA_[1] = float(c.a.y()), coarseA_[2] = float(c.a.z()), coarseA_[3] = float(c.b);
}

namespace {

template <class Visit>
void forPatches(const Vector3f& x, const Vector3f& origin, float invCell, const Eigen::Vector3i& dims,
                const std::vector<uint32_t>& start, const std::vector<uint32_t>& list, Visit visit) {
    Vector3f u = (x - origin) * invCell;
    if (!(u.minCoeff() >= 0.0f) || !(u.x() < float(dims.x()) && u.y() < float(dims.y()) && u.z() < float(dims.z())))
        return;
    size_t cell = size_t(u.x()) + size_t(dims.x()) * (size_t(u.y()) + size_t(dims.y()) * size_t(u.z()));
    for (uint32_t k = start[cell]; k < start[cell + 1]; ++k) visit(list[k]);
}

}  // namespace

float PuFloat::farField(const Vector3f& x, Vector3f& g, Eigen::Matrix3f* H) const {
    float f = coarseA_[0] * x.x() + coarseA_[1] * x.y() + coarseA_[2] * x.z() + coarseA_[3];
    g = Vector3f(coarseA_[0], coarseA_[1], coarseA_[2]);
    for (size_t j = 0; j < coarse_.size(); j += 8)
        addR3Node<float>(x, Vector3f(&coarse_[j]), coarse_[j + 3], Vector3f(&coarse_[j + 4]), f, g, H);
    return f;
}

float PuFloat::eval(const Vector3f& x, Vector3f& gradient) const {
    using A4 = Eigen::Array4f;
    Blend<float> blend{false};
    const Eigen::Matrix3f zero = Eigen::Matrix3f::Zero();
    forPatches(x, origin_, invCell_, dims_, *cellStart_, *cellPatches_, [&](uint32_t i) {
        const Patch& p = patches_[i];
        Vector3f q = (x - Vector3f(p.cx, p.cy, p.cz)) / p.radius;
        if (!(q.squaredNorm() < 1.0f)) return;
        A4 f = A4::Zero(), gx = A4::Zero(), gy = A4::Zero(), gz = A4::Zero();
        for (uint32_t j = p.first; j < p.first + p.count; j += 4) {
            A4 dx = q.x() - A4::Map(&px_[j]), dy = q.y() - A4::Map(&py_[j]), dz = q.z() - A4::Map(&pz_[j]);
            A4 r = (dx * dx + dy * dy + dz * dz).sqrt();
            A4 Bx = A4::Map(&bx_[j]), By = A4::Map(&by_[j]), Bz = A4::Map(&bz_[j]);
            A4 db = dx * Bx + dy * By + dz * Bz;
            A4 inv = (r > 0.0f).select(A4(r.inverse()), 0.0f);
            A4 A = A4::Map(&alpha_[j]), tr = 3.0f * r;
            f += A * r * r * r - tr * db;
            A4 s = 3.0f * (A * r - db * inv);
            gx += s * dx - tr * Bx;
            gy += s * dy - tr * By;
            gz += s * dz - tr * Bz;
        }
        Vector3f g(p.ax + gx.sum(), p.ay + gy.sum(), p.az + gz.sum());
        blend.addPatch(q, p.radius, p.ax * q.x() + p.ay * q.y() + p.az * q.z() + p.b + f.sum(), g, zero);
    });
    auto far = [&](Vector3f& g, Eigen::Matrix3f* H) { return farField(x, g, H); };
    return blend.finish(tau_, far, gradient, nullptr);
}

std::vector<Eigen::Vector4f> PuFloat::evalMany(const std::vector<Vector3d>& points) const {
    const size_t n = points.size(), cells = cellStart_->size() - 1;
    // A counting sort by cell (the points outside the grid last).
    std::vector<uint32_t> cellOf(n), start(cells + 2, 0), order(n);
    for (size_t i = 0; i < n; ++i) {
        const Vector3f u = (points[i].cast<float>() - origin_) * invCell_;
        size_t cell = cells;
        if (u.minCoeff() >= 0.0f && u.x() < float(dims_.x()) && u.y() < float(dims_.y()) && u.z() < float(dims_.z()))
            cell = size_t(u.x()) + size_t(dims_.x()) * (size_t(u.y()) + size_t(dims_.y()) * size_t(u.z()));
        cellOf[i] = uint32_t(cell);
        ++start[cell + 1];
    }
    for (size_t c = 0; c <= cells; ++c) start[c + 1] += start[c];
    for (size_t i = 0; i < n; ++i) order[start[cellOf[i]]++] = uint32_t(i);
    std::vector<Eigen::Vector4f> out(n);
    parallelChunks(n, 4096, [&](size_t begin, size_t end, size_t) {
        for (size_t k = begin; k < end; ++k) {
            const uint32_t i = order[k];
            Vector3f g;
            const float f = eval(points[i].cast<float>(), g);
            out[i] = Eigen::Vector4f(g.x(), g.y(), g.z(), f);
        }
    });
    return out;
}

float PuFloat::evalHessian(const Vector3f& x, Vector3f& gradient, Eigen::Matrix3f& hessian) const {
    Blend<float> blend{true};
    forPatches(x, origin_, invCell_, dims_, *cellStart_, *cellPatches_, [&](uint32_t i) {
        const Patch& p = patches_[i];
        Vector3f q = (x - Vector3f(p.cx, p.cy, p.cz)) / p.radius;
        if (!(q.squaredNorm() < 1.0f)) return;
        Vector3f a(p.ax, p.ay, p.az), g = a;
        float f = a.dot(q) + p.b;
        Eigen::Matrix3f H = Eigen::Matrix3f::Zero();
        for (uint32_t j = p.first; j < p.first + p.count; ++j)
            addR3Node<float>(q, Vector3f(px_[j], py_[j], pz_[j]), alpha_[j], Vector3f(bx_[j], by_[j], bz_[j]), f, g,
                             &H);
        blend.addPatch(q, p.radius, f, g, H);
    });
    auto far = [&](Vector3f& g, Eigen::Matrix3f* H) { return farField(x, g, H); };
    return blend.finish(tau_, far, gradient, &hessian);
}

}  // namespace ink
