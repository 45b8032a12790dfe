// The CPU reference of refine.comp / scan.comp / compact.comp: the same plan, rules, double arithmetic and
// random numbers, so that its points match the GPU's (up to the drivers' rounding) and its speed is a fair
// comparison. Each level is split across threads; compaction is sequential and stable.
#include "random.h"
#include "refine.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <thread>

namespace ink {

using Eigen::Vector3f;

namespace {

constexpr uint32_t kKept = DropReasonCount;

using Eigen::Vector3d;

// Eq. 11 with the Armijo rule, in double as in refine.comp.
struct Projector {
    const Hrbf& h;
    const LevelParams& pc;

    uint32_t project(Vector3d& p, Vector3d& grad) const {
        Vector3d g;
        double f = h.eval(p, g);
        for (uint32_t it = 0;; ++it) {
            double gg = g.dot(g);
            if (gg < double(pc.eps2) * double(pc.eps2)) return DropGradient;
            if (std::abs(f) < double(pc.eps1) * std::sqrt(gg)) {
                grad = g;
                return kKept;
            }
            if (it == pc.maxIterations) return DropIterations;
            Vector3d step = (f / gg) * g;
            double t = 1.0;
            for (uint32_t i = 0;; ++i) {
                Vector3d gq;
                Vector3d q = p - t * step;
                double fq = h.eval(q, gq);
                if (fq * fq <= f * f * (1.0 - 2.0 * double(pc.phi) * t)) {
                    p = q;
                    f = fq;
                    g = gq;
                    break;
                }
                if (i == 16) return DropArmijo;
                t *= double(pc.delta);
            }
        }
    }
};

Vector3f perpendicular(const Vector3f& n) {
    float s = n.z() >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z());
    return {1.0f + s * n.x() * n.x() * a, s * n.x() * n.y() * a, -s * n.x()};
}

void randomFrame(const LevelParams& pc, const Vector3f& n, uint32_t parent, Vector3f& r, Vector3f& u) {
    auto q = unitFloats(pcg4d({pc.seed, pc.level, parent, 0xFFFFFFFFu}));
    float z = 1.0f - 2.0f * q[0], phi = 6.28318530718f * q[1], theta = 6.28318530718f * q[2];
    float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    Vector3f axis(s * std::cos(phi), s * std::sin(phi), z);
    Vector3f rp = n * std::cos(theta) + axis.cross(n) * std::sin(theta) + axis * axis.dot(n) * (1.0f - std::cos(theta));
    Vector3f c = n.cross(rp);
    u = c.dot(c) > 1e-12f ? c.normalized() : perpendicular(n);
    r = n.cross(u);
}

Vector3f tangentDirection(const Hrbf& hrbf, const LevelParams& pc, const Vector3f& position, const Vector3f& n,
                          const Vector3f& fallback) {
    if (pc.direction == 0) {
        Vector3f axis(pc.axis[0], pc.axis[1], pc.axis[2]);
        Vector3f d = axis - axis.dot(n) * n;
        return d.dot(d) > 1e-8f ? d.normalized() : fallback;
    }
    // The same 2×2 shape operator in the same tangent basis as refine.comp, so both pick the same vector.
    Eigen::Vector3d gd;
    Eigen::Matrix3d Hd;
    hrbf.eval(position.cast<double>(), gd, &Hd);
    Eigen::Matrix3f H = Hd.cast<float>();
    float gn = float(gd.norm());
    Vector3f t1 = perpendicular(n), t2 = n.cross(t1);
    float a = t1.dot(H * t1) / gn, b = t1.dot(H * t2) / gn, c = t2.dot(H * t2) / gn;
    float mean = 0.5f * (a + c), radius = std::sqrt(0.25f * (a - c) * (a - c) + b * b);
    if (radius < 1e-6f * (std::abs(mean) + 1e-6f)) return fallback;
    float k = pc.direction == 1 ? mean - radius : mean + radius;
    Eigen::Vector2f e = std::abs(k - a) + std::abs(b) > std::abs(k - c) + std::abs(b) ? Eigen::Vector2f(b, k - a)
                                                                                      : Eigen::Vector2f(k - c, b);
    return (e.x() * t1 + e.y() * t2).normalized();
}

}  // namespace

std::vector<PointRecord> refineOnCpu(const Hrbf& hrbf, const RefineOptions& options, const RefinePlan& plan,
                                     std::vector<LevelStats>* stats, unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<PointRecord> points;
    points.reserve(plan.maxPoints);
    std::vector<LevelStats> levelStats(plan.levelCount);
    size_t parentOffset = 0, parentCount = 0;
    size_t drawFirst = 0;

    for (uint32_t level = 0; level < plan.levelCount; ++level) {
        LevelParams pc = levelParams(plan, options, level);
        Projector projector{hrbf, pc};
        size_t count = level == 0 ? plan.seeds.size() : parentCount * pc.childCount;
        std::vector<PointRecord> candidates(count);
        std::vector<uint32_t> result(count);

        auto work = [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                uint32_t parentIndex = uint32_t(i / pc.childCount), child = uint32_t(i % pc.childCount);
                auto rnd = unitFloats(pcg4d({pc.seed, level, parentIndex, child}));
                Vector3f origin, start;
                if (pc.mode == 0) {
                    origin = plan.seeds[i];
                    start = origin;
                } else {
                    const PointRecord& parent = points[parentOffset + parentIndex];
                    origin = Vector3f(parent.position[0], parent.position[1], parent.position[2]);
                    Vector3f n(parent.normal[0], parent.normal[1], parent.normal[2]);
                    Vector3f r, u;
                    randomFrame(pc, n, parentIndex, r, u);
                    if (pc.mode == 1) {
                        float si = (child & 1u) ? 1.0f : -1.0f, sj = (child & 2u) ? 1.0f : -1.0f;
                        float mi = 0.25f * rnd[0] - 0.125f, mj = 0.25f * rnd[1] - 0.125f;
                        start = origin + (si + mi) * pc.rho * r + (sj + mj) * pc.rho * u;
                    } else {
                        Vector3f d = tangentDirection(hrbf, pc, origin, n, r);
                        start = origin + (child == 0 ? -pc.rho : pc.rho) * d;
                    }
                }
                Vector3d p = start.cast<double>(), g = Vector3d::Zero();
                uint32_t res = projector.project(p, g);
                if (res == kKept && (p.cast<float>() - origin).norm() > pc.jumpLimit) res = DropJump;
                result[i] = res;
                if (res == kKept) {
                    Vector3f n = g.normalized().cast<float>();
                    candidates[i] = {{float(p.x()), float(p.y()), float(p.z())}, level, {n.x(), n.y(), n.z()}, pc.toneOffset + pc.toneScale * rnd[2]};
                }
            }
        };
        std::vector<std::thread> pool;
        size_t chunk = (count + threads - 1) / threads;
        for (unsigned t = 0; t < threads && t * chunk < count; ++t)
            pool.emplace_back(work, t * chunk, std::min(count, (t + 1) * chunk));
        for (auto& th : pool) th.join();

        LevelStats& s = levelStats[level];
        s.level = level;
        s.candidates = uint32_t(count);
        size_t offset = points.size();
        for (size_t i = 0; i < count; ++i) {
            if (result[i] == kKept)
                points.push_back(candidates[i]);
            else
                s.dropped[result[i]]++;
        }
        s.kept = uint32_t(points.size() - offset);
        parentOffset = offset;
        parentCount = s.kept;
        if (!options.keepAllLevels) drawFirst = offset;
    }
    if (stats) *stats = levelStats;
    return std::vector<PointRecord>(points.begin() + std::ptrdiff_t(drawFirst), points.end());
}

}  // namespace ink
