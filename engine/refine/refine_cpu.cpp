// The CPU reference of refine.comp / scan.comp / compact.comp: the same plan, rules, double arithmetic and
// random numbers, so that its points match the GPU's (up to the drivers' rounding) and its speed is a fair
// comparison. Each level is split across threads; compaction is sequential and stable.
#include "base/common.h"
#include "base/random.h"
#include "refine/refine_plan.h"

// The AVX2+FMA evaluation exists only where it can be compiled: x86-64 with GCC or Clang (target attributes,
// __builtin_cpu_supports). Everywhere else (ARM64, ...) the portable path is the only one.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define INKWELL_REFINE_AVX2 1
#include <immintrin.h>
#else
#define INKWELL_REFINE_AVX2 0
#endif

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <thread>

namespace ink {

using Eigen::Vector3f;

namespace {

constexpr uint32_t kKept = DropReasonCount;

using Eigen::Vector3d;

// f and ∇f over centres stored as arrays (structure of arrays), so that the loop runs 4 centres at a time: in
// AVX2 registers where the CPU has them (chosen at run time on x86-64), otherwise on Eigen arrays of 4 (the
// portable path). The CPU reference is plain vectorized C++, a fair peer for the GPU.
struct HrbfArrays {
    std::vector<double> px, py, pz, alpha, bx, by, bz;
    Vector3d a;
    double b;

    HrbfArrays(const Hrbf& h, CpuKernel kernel) : a(h.a), b(h.b) {
#if INKWELL_REFINE_AVX2
        avx2 = avx2 && kernel == CpuKernel::Best;
#else
        (void)kernel;
#endif
        size_t m = h.size(), padded = (m + 3) / 4 * 4;  // zero centres pad to a multiple of 4: α = β = 0
        for (auto* v : {&px, &py, &pz, &alpha, &bx, &by, &bz}) v->assign(padded, 0.0);
        for (size_t j = 0; j < m; ++j) {
            px[j] = h.centers[j].x(), py[j] = h.centers[j].y(), pz[j] = h.centers[j].z();
            alpha[j] = h.alpha[j];
            bx[j] = h.beta[j].x(), by[j] = h.beta[j].y(), bz[j] = h.beta[j].z();
        }
    }

#if INKWELL_REFINE_AVX2
    double eval(const Vector3d& x, Vector3d& g) const { return avx2 ? evalAvx2(x, g) : evalPortable(x, g); }
#else
    double eval(const Vector3d& x, Vector3d& g) const { return evalPortable(x, g); }
#endif

private:
    // The portable path: the AVX2 path's arithmetic, term for term, on Eigen arrays of 4 centres, which Eigen
    // evaluates in the SIMD registers the target always has (SSE2 on x86-64, NEON on ARM64), 2 doubles at a
    // time. Lane k sums the centres j ≡ k (mod 4), and the lanes are added up in the AVX2 path's order, so the
    // results differ from the AVX2 path's only in the roundings of its fused multiply-adds (which a compiler may
    // also contract here, as GCC does on ARM64).
    double evalPortable(const Vector3d& x, Vector3d& grad) const {
        using A4 = Eigen::Array4d;
        A4 f = A4::Zero(), gx = A4::Zero(), gy = A4::Zero(), gz = A4::Zero();
        for (size_t j = 0; j < px.size(); j += 4) {
            A4 dx = x.x() - A4::Map(&px[j]), dy = x.y() - A4::Map(&py[j]), dz = x.z() - A4::Map(&pz[j]);
            A4 r2 = dx * dx + dy * dy + dz * dz, r = r2.sqrt();
            A4 Bx = A4::Map(&bx[j]), By = A4::Map(&by[j]), Bz = A4::Map(&bz[j]);
            A4 db = dx * Bx + dy * By + dz * Bz;
            A4 inv = (r > 0.0).select(A4(r.inverse()), 0.0);
            A4 A = A4::Map(&alpha[j]);
            A4 r3 = r2 * r, tr = 3.0 * r;
            f += A * r3 - tr * db;
            A4 s = 3.0 * (A * r - db * inv);  // ∇: 3α r d − 3(r β + d ⟨d,β⟩/r)
            gx += s * dx - tr * Bx;
            gy += s * dy - tr * By;
            gz += s * dz - tr * Bz;
        }
        auto total = [](const A4& v) { return (v[0] + v[2]) + (v[1] + v[3]); };
        grad = {a.x() + total(gx), a.y() + total(gy), a.z() + total(gz)};
        return a.dot(x) + b + total(f);
    }

#if INKWELL_REFINE_AVX2
    bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");

    __attribute__((target("avx2,fma"))) static double sum(__m256d v) {
        __m128d lo = _mm256_castpd256_pd128(v), hi = _mm256_extractf128_pd(v, 1);
        lo = _mm_add_pd(lo, hi);
        return _mm_cvtsd_f64(_mm_add_sd(lo, _mm_unpackhi_pd(lo, lo)));
    }

    __attribute__((target("avx2,fma"))) double evalAvx2(const Vector3d& x, Vector3d& grad) const {
        const __m256d X = _mm256_set1_pd(x.x()), Y = _mm256_set1_pd(x.y()), Z = _mm256_set1_pd(x.z());
        const __m256d three = _mm256_set1_pd(3.0), zero = _mm256_setzero_pd();
        __m256d f = zero, gx = zero, gy = zero, gz = zero;
        for (size_t j = 0; j < px.size(); j += 4) {
            __m256d dx = _mm256_sub_pd(X, _mm256_loadu_pd(&px[j]));
            __m256d dy = _mm256_sub_pd(Y, _mm256_loadu_pd(&py[j]));
            __m256d dz = _mm256_sub_pd(Z, _mm256_loadu_pd(&pz[j]));
            __m256d r2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
            __m256d r = _mm256_sqrt_pd(r2);
            __m256d Bx = _mm256_loadu_pd(&bx[j]), By = _mm256_loadu_pd(&by[j]), Bz = _mm256_loadu_pd(&bz[j]);
            __m256d db = _mm256_fmadd_pd(dz, Bz, _mm256_fmadd_pd(dy, By, _mm256_mul_pd(dx, Bx)));
            __m256d inv = _mm256_and_pd(_mm256_div_pd(_mm256_set1_pd(1.0), r), _mm256_cmp_pd(r, zero, _CMP_GT_OQ));
            __m256d A = _mm256_loadu_pd(&alpha[j]);
            __m256d r3 = _mm256_mul_pd(r2, r), tr = _mm256_mul_pd(three, r);
            f = _mm256_add_pd(f, _mm256_fnmadd_pd(tr, db, _mm256_mul_pd(A, r3)));
            __m256d s = _mm256_mul_pd(three, _mm256_fmsub_pd(A, r, _mm256_mul_pd(db, inv)));
            gx = _mm256_add_pd(gx, _mm256_fnmadd_pd(tr, Bx, _mm256_mul_pd(s, dx)));
            gy = _mm256_add_pd(gy, _mm256_fnmadd_pd(tr, By, _mm256_mul_pd(s, dy)));
            gz = _mm256_add_pd(gz, _mm256_fnmadd_pd(tr, Bz, _mm256_mul_pd(s, dz)));
        }
        grad = {a.x() + sum(gx), a.y() + sum(gy), a.z() + sum(gz)};
        return a.dot(x) + b + sum(f);
    }
#endif
};

// Eq. 11 with the Armijo rule, in the arithmetic of refine.comp: float for the partition of unity (PuFloat),
// double for the global fit (HrbfArrays).
template <class Eval, class T>
struct Projector {
    using V = Eigen::Matrix<T, 3, 1>;
    const Eval& h;
    const LevelParams& pc;

    uint32_t project(V& p, V& grad) const {
        V g;
        T f = h.eval(p, g);
        for (uint32_t it = 0;; ++it) {
            T gg = g.dot(g);
            if (gg < T(pc.eps2) * T(pc.eps2)) return DropGradient;
            if (std::abs(f) < T(pc.eps1) * std::sqrt(gg)) {
                grad = g;
                return kKept;
            }
            if (it == pc.maxIterations) return DropIterations;
            V step = (f / gg) * g;
            T t = 1;
            for (uint32_t i = 0;; ++i) {
                V gq;
                V q = p - t * step;
                T fq = h.eval(q, gq);
                if (fq * fq <= f * f * (T(1) - T(2) * T(pc.phi) * t)) {
                    p = q;
                    f = fq;
                    g = gq;
                    break;
                }
                if (i == 16) return DropArmijo;
                t *= T(pc.delta);
            }
        }
    }
};

Vector3f perpendicular(const Vector3f& n) {
    float s = n.z() >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z());
    return {1.0f + s * n.x() * n.x() * a, s * n.x() * n.y() * a, -s * n.x()};
}

void randomFrame(const LevelParams& pc, const Vector3f& n, uint32_t parent, uint32_t pass, Vector3f& r, Vector3f& u) {
    auto q = unitFloats(pcg4d({pc.seed, pc.level, parent, 0xFFFFFFFFu - pass}));
    float z = 1.0f - 2.0f * q[0], phi = 6.28318530718f * q[1], theta = 6.28318530718f * q[2];
    float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    Vector3f axis(s * std::cos(phi), s * std::sin(phi), z);
    Vector3f rp = n * std::cos(theta) + axis.cross(n) * std::sin(theta) + axis * axis.dot(n) * (1.0f - std::cos(theta));
    Vector3f c = n.cross(rp);
    u = c.dot(c) > 1e-12f ? c.normalized() : perpendicular(n);
    r = n.cross(u);
}

Vector3f tangentDirection(const Surface& hrbf, const PuFloat* pu, const LevelParams& pc, const Vector3f& position,
                          const Vector3f& n, const Vector3f& fallback) {
    if (pc.direction == 0) {
        Vector3f axis(pc.axis[0], pc.axis[1], pc.axis[2]);
        Vector3f d = axis - axis.dot(n) * n;
        return d.dot(d) > 1e-8f ? d.normalized() : fallback;
    }
    // The same 2×2 shape operator in the same tangent basis as refine.comp, so both pick the same vector.
    Eigen::Matrix3f H;
    float gn;
    if (pu) {
        Vector3f g;
        pu->evalHessian(position, g, H);
        gn = g.norm();
    } else {
        Eigen::Vector3d gd;
        Eigen::Matrix3d Hd;
        hrbf.global.eval(position.cast<double>(), gd, &Hd);
        H = Hd.cast<float>();
        gn = float(gd.norm());
    }
    Vector3f t1 = perpendicular(n), t2 = n.cross(t1);
    float a = t1.dot(H * t1) / gn, b = t1.dot(H * t2) / gn, c = t2.dot(H * t2) / gn;
    float mean = 0.5f * (a + c), radius = std::sqrt(0.25f * (a - c) * (a - c) + b * b);
    if (radius < 1e-6f * (std::abs(mean) + 1e-6f)) return fallback;
    float k = pc.direction == 1 ? mean - radius : mean + radius;
    Eigen::Vector2f e = std::abs(k - a) + std::abs(b) > std::abs(k - c) + std::abs(b) ? Eigen::Vector2f(b, k - a)
                                                                                      : Eigen::Vector2f(k - c, b);
    if (e.x() < 0 || (e.x() == 0 && e.y() < 0)) e = -e;  // one sign for the line field, as refine_body.glsl
    return (e.x() * t1 + e.y() * t2).normalized();
}

}  // namespace

std::vector<PointRecord> refineOnCpu(const Surface& hrbf, const RefineOptions& options, const RefinePlan& plan,
                                     std::vector<LevelStats>* stats, unsigned threads, CpuKernel kernel) {
    if (plan.maxPoints > kMaxCpuPoints)
        throw Error("the refinement asks for up to " + std::to_string(plan.maxPoints) + " points, but at most " +
                    std::to_string(kMaxCpuPoints) + " fit the CPU reference: plan it with kMaxCpuPoints");
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const bool global = hrbf.method == FitMethod::Global;
    std::unique_ptr<HrbfArrays> arrays;
    std::unique_ptr<PuFloat> pu;
    if (global)
        arrays = std::make_unique<HrbfArrays>(hrbf.global, kernel);
    else
        pu = std::make_unique<PuFloat>(hrbf.pu);
    std::vector<PointRecord> points;
    points.reserve(plan.maxPoints);
    std::vector<LevelStats> levelStats(plan.levelCount);
    size_t parentOffset = 0, parentCount = 0;
    size_t drawFirst = 0;

    for (uint32_t level = 0; level < plan.levelCount; ++level) {
        LevelParams pc = levelParams(plan, options, level);
        size_t count = level == 0 ? plan.seeds.size() : parentCount * pc.childCount;
        std::vector<PointRecord> candidates(count);
        std::vector<uint32_t> result(count);

        auto work = [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                uint32_t parentIndex = uint32_t(i / pc.childCount), child = uint32_t(i % pc.childCount);
                uint32_t pass = child / pc.passChildren, sub = child % pc.passChildren;
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
                    randomFrame(pc, n, parentIndex, pass, r, u);
                    if (pc.mode == 1) {
                        float si = (sub & 1u) ? 1.0f : -1.0f, sj = (sub & 2u) ? 1.0f : -1.0f;
                        float mi = 0.25f * rnd[0] - 0.125f, mj = 0.25f * rnd[1] - 0.125f;
                        start = origin + (si + mi) * pc.rho * r + (sj + mj) * pc.rho * u;
                    } else {
                        Vector3f d = tangentDirection(hrbf, pu.get(), pc, origin, n, r);
                        start = origin + (sub == 0 ? -pc.rho : pc.rho) * d;
                        if (pass > 0) start += (2.0f * rnd[1] - 1.0f) * pc.rho * n.cross(d);
                    }
                }
                Vector3f p, n;
                uint32_t res;
                if (pu) {
                    Vector3f g = Vector3f::Zero();
                    p = start;
                    res = Projector<PuFloat, float>{*pu, pc}.project(p, g);
                    n = g.normalized();
                } else {
                    Vector3d pd = start.cast<double>(), g = Vector3d::Zero();
                    res = Projector<HrbfArrays, double>{*arrays, pc}.project(pd, g);
                    p = pd.cast<float>();
                    n = g.normalized().cast<float>();
                }
                if (res == kKept && (p - origin).norm() > pc.jumpLimit) res = DropJump;
                result[i] = res;
                if (res == kKept) {
                    candidates[i] = {{float(p.x()), float(p.y()), float(p.z())},
                                     level,
                                     {n.x(), n.y(), n.z()},
                                     pc.toneOffset + pc.toneScale * rnd[2]};
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
