// Contour and hatching strokes (lines.h), traced on the CPU in object space.
#include "lines.h"

#include "common.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>
#include <unordered_map>

namespace ink {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector3f;

double PenStroke::length() const {
    double l = 0;
    for (size_t i = 1; i < points.size(); ++i) l += (points[i] - points[i - 1]).norm();
    if (closed && points.size() > 1) l += (points.front() - points.back()).norm();
    return l;
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Points of strokes in a uniform grid hashed by cell, for "is any point of another stroke within r" queries
// with r at most the cell side (27 cells a query).
class PointHash {
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
    static uint64_t key(const Eigen::Array3i& c) {
        return (uint64_t(uint32_t(c.x()) & 0x1FFFFF) << 42) | (uint64_t(uint32_t(c.y()) & 0x1FFFFF) << 21) |
               uint64_t(uint32_t(c.z()) & 0x1FFFFF);
    }
    double inv_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
    std::vector<Entry> entries_;
};

// ---- Contours ---------------------------------------------------------------------------------------------------

struct ContourEval {
    double f, g;
    Vector3d gradF, gradG;
};

ContourEval evalContour(const Surface& hrbf, const Vector3d& eye, const Vector3d& x) {
    Vector3d gradient;
    Matrix3d hessian;
    double f = hrbf.eval(x, gradient, &hessian);
    Vector3d r = x - eye;
    return {f, gradient.dot(r), gradient, hessian * r + gradient};
}

// Newton on (f, g) = 0 with the minimum-norm step of the 2×3 system. `last` gets the evaluation of the last
// iteration, taken within 1e-9 of the point returned: the next step's tangent.
bool contourNewton(const Surface& hrbf, const Vector3d& eye, Vector3d& x, double maxMove, int iterations = 10,
                   ContourEval* last = nullptr) {
    const Vector3d start = x;
    for (int i = 0; i < iterations; ++i) {
        ContourEval e = evalContour(hrbf, eye, x);
        if (last) *last = e;
        double a = e.gradF.squaredNorm(), b = e.gradF.dot(e.gradG), c = e.gradG.squaredNorm();
        double det = a * c - b * b;
        if (!(det > 1e-14 * a * c)) return false;  // ∇f ∥ ∇g: a singular point of the contour
        double y0 = (c * e.f - b * e.g) / det, y1 = (a * e.g - b * e.f) / det;
        Vector3d dx = -(y0 * e.gradF + y1 * e.gradG);
        x += dx;
        if (!x.allFinite() || (x - start).norm() > maxMove) return false;
        if (dx.norm() < 1e-9) return true;
    }
    return false;
}

}  // namespace

bool projectToContour(const Surface& hrbf, const Vector3d& eye, Vector3d& x) {
    return contourNewton(hrbf, eye, x, 0.05);
}

std::vector<PenStroke> traceContours(const Surface& hrbf, const Vector3d& eye, const std::vector<SurfaceSample>& seeds,
                                     const ContourOptions& options, ContourStats* stats) {
    auto start = std::chrono::steady_clock::now();
    ContourStats s;
    const double step = options.step;
    // Seeds nearest the contour first.
    std::vector<std::pair<double, uint32_t>> order;
    for (uint32_t i = 0; i < seeds.size(); ++i) {
        Vector3d v = (eye - seeds[i].position).normalized();
        double nv = std::abs(seeds[i].normal.dot(v));
        if (nv < options.seedBand) order.push_back({nv, i});
    }
    std::sort(order.begin(), order.end());

    PointHash traced(4.0 * step), tried(3.0 * step);
    std::vector<PenStroke> pieces;
    uint32_t curveId = 0;
    Progress progress("contours", order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        progress.update(k);
        const uint32_t index = order[k].second;
        Vector3d x0 = seeds[index].position;
        // Most seeds lie beside a traced curve, or beside a seed that led nowhere.
        if (traced.near(x0, seeds[index].normal, 4.0 * step) || tried.near(x0, seeds[index].normal, 3.0 * step))
            continue;
        ++s.seedsTried;
        tried.add(x0, seeds[index].normal, 0, 0);
        if (!contourNewton(hrbf, eye, x0, 8 * step, 5)) continue;
        if (traced.near(x0, seeds[index].normal, 2.0 * step)) continue;  // on a curve already traced

        // March one way until the curve closes (it always does, generically) or cannot go on, then the other.
        std::vector<Vector3d> forward, backward;
        bool closed = false;
        const size_t hashStart = traced.size();
        auto march = [&](double sign, std::vector<Vector3d>& out) {
            Vector3d x = x0, previous = Vector3d::Zero();
            double h = step, arc = 0;
            ContourEval e = evalContour(hrbf, eye, x), next;
            while (out.size() < options.maxVertices) {
                Vector3d t = e.gradF.cross(e.gradG);
                if (!(t.norm() > 1e-12 * e.gradF.norm() * e.gradG.norm())) return;
                t.normalize();
                if (previous.isZero())
                    t *= sign;
                else if (t.dot(previous) < 0)
                    t = -t;
                if (!previous.isZero()) {
                    // Shorter steps where the curve turns: the chord stays within a fraction of a pixel.
                    double turn = std::acos(std::clamp(t.dot(previous), -1.0, 1.0));
                    if (turn > 0.15)
                        h = std::max(step / 16, h * 0.5);
                    else if (turn < 0.05)
                        h = std::min(2 * step, h * 1.5);
                }
                Vector3d y = x + h * t;
                if (!contourNewton(hrbf, eye, y, 2 * h, 10, &next)) {
                    if (h <= step / 16) return;
                    h *= 0.5;
                    continue;
                }
                arc += (y - x).norm();
                if (arc > 3 * step && (y - x0).norm() < 1.2 * h) {
                    closed = true;
                    return;
                }
                Vector3d n = e.gradF.normalized();
                // Ran into another curve, or into itself more than 20 steps back along it (arcs are signed: the
                // backward march counts down from the seed): a curve that missed its own start would otherwise go
                // round again until maxVertices.
                if (traced.near(y, n, 0.5 * step, curveId, sign * arc, 20 * step)) return;
                traced.add(y, n, curveId, sign * arc);
                out.push_back(y);
                previous = t;
                x = y;
                e = next;
            }
        };
        march(1.0, forward);
        if (!closed) march(-1.0, backward);
        std::vector<Vector3d> curve(backward.rbegin(), backward.rend());
        curve.push_back(x0);
        curve.insert(curve.end(), forward.begin(), forward.end());
        double loop = 0;
        for (size_t i = 1; i < curve.size(); ++i) loop += (curve[i] - curve[i - 1]).norm();
        if (curve.size() < 4 || (closed && loop < options.minLoopLength)) {
            s.smallLoops += curve.size() >= 4;
            traced.truncate(hashStart);
            continue;
        }
        if (s.vertices + curve.size() > options.maxTotalVertices || secondsSince(start) > options.maxSeconds)
            throw Error("the contour of this view passed " +
                        (s.vertices + curve.size() > options.maxTotalVertices
                             ? std::to_string(options.maxTotalVertices) + " vertices"
                             : std::to_string(int(options.maxSeconds)) + " seconds of tracing") +
                        " after " + std::to_string(s.curves) + " curves and " + std::to_string(s.cusps) +
                        " cusps: the surface is too rough to draw lines on (a noisy fit?); draw dots instead, or "
                        "fit fewer points (--control-points)");
        traced.add(x0, seeds[index].normal, curveId, 0);
        ++s.curves;
        s.closedCurves += closed;
        s.vertices += curve.size();

        // Normals, and the cusps: where the image of the curve reverses, i.e. the tangent's component along
        // w = n × v (the tangent plane's direction across the view ray) changes sign.
        const size_t m = curve.size();
        std::vector<Vector3d> normals(m);
        std::vector<double> across(m);
        for (size_t i = 0; i < m; ++i) {
            Vector3d gradient;
            hrbf.eval(curve[i], gradient);
            normals[i] = gradient.normalized();
            size_t prev = i > 0 ? i - 1 : (closed ? m - 1 : i), next = i + 1 < m ? i + 1 : (closed ? 0 : i);
            Vector3d t = curve[next] - curve[prev];
            across[i] = t.dot(normals[i].cross((curve[i] - eye).normalized()));
        }
        std::vector<size_t> cusps;
        for (size_t i = 0; i + (closed ? 0 : 1) < m; ++i) {
            size_t j = (i + 1) % m;
            if ((across[i] < 0) != (across[j] < 0)) cusps.push_back(std::abs(across[i]) < std::abs(across[j]) ? i : j);
        }
        s.cusps += cusps.size();
        auto piece = [&](size_t from, size_t count, bool isClosed) {
            PenStroke p;
            p.closed = isClosed;
            p.curve = curveId;
            for (size_t k = 0; k < count; ++k) {
                size_t i = (from + k) % m;
                p.points.push_back(curve[i].cast<float>());
                p.normals.push_back(normals[i].cast<float>());
            }
            if (p.points.size() >= 2) pieces.push_back(std::move(p));
        };
        if (cusps.empty()) {
            piece(0, m, closed);
        } else if (closed) {
            for (size_t k = 0; k < cusps.size(); ++k) {
                size_t a = cusps[k], b = cusps[(k + 1) % cusps.size()];
                piece(a, (b + m - a) % m + 1 + (cusps.size() == 1 ? m : 0), false);
            }
        } else {
            size_t a = 0;
            for (size_t c : cusps) {
                piece(a, c - a + 1, false);
                a = c;
            }
            piece(a, m - a, false);
        }
        ++curveId;
    }
    s.pieces = pieces.size();
    s.seconds = secondsSince(start);
    if (stats) *stats = s;
    return pieces;
}

// ---- Hatching ---------------------------------------------------------------------------------------------------

namespace {

// Newton steps along ∇f onto f = 0; n is the unit normal there.
bool projectToSurface(const Surface& hrbf, Vector3d& x, Vector3d& n) {
    for (int i = 0; i < 8; ++i) {
        Vector3d gradient;
        double f = hrbf.eval(x, gradient);
        double g2 = gradient.squaredNorm();
        if (!(g2 > 1e-16) || !std::isfinite(f)) return false;
        n = gradient / std::sqrt(g2);
        if (std::abs(f) < 1e-8 * std::sqrt(g2)) return true;
        x -= (f / g2) * gradient;
    }
    return false;
}

class Hatcher {
public:
    Hatcher(const Surface& hrbf, const std::vector<SurfaceSample>& samples, const HatchOptions& o, uint32_t family)
        : hrbf_(hrbf),
          samples_(samples),
          o_(o),
          family_(family),
          hash_(0.9 * o.spacing * double(1u << (std::max(1u, o.levels) - 1))),
          step_(0.5 * o.spacing) {}

    std::vector<PenStroke> run() {
        for (uint32_t level = 0; level < std::max(1u, o_.levels); ++level) {
            const double dsep = o_.spacing * double(1u << (o_.levels - 1 - level));
            size_t queue = 0;  // Jobard & Lefer: seeds beside the strokes traced so far, oldest first
            size_t sample = 0;
            while (true) {
                if (queue < strokes_.size()) {
                    seedBeside(queue++, level, dsep);
                    continue;
                }
                // The queue is empty: the next sample far enough from every stroke starts a new region.
                bool started = false;
                for (; sample < samples_.size() && !started; ++sample)
                    started = tryStroke(samples_[sample].position, level, dsep, &samples_[sample].normal);
                if (!started) break;
            }
        }
        return std::move(strokes_);
    }

private:
    // The field's unit direction at x (normal n) for this family; false where it vanishes.
    bool field(const Vector3d& n, Vector3d& d) const {
        d = o_.axis - o_.axis.dot(n) * n;
        if (!(d.norm() > 0.2 * o_.axis.norm())) return false;  // near a pole of the axis field
        d.normalize();
        if (family_ == 1) d = n.cross(d);
        return true;
    }

    // Seeds at the separation on both sides of stroke k (tracing appends to strokes_: no references into it).
    void seedBeside(size_t k, uint32_t level, double dsep) {
        for (size_t i = 0; i < strokes_[k].points.size(); i += 2) {
            Vector3d p = strokes_[k].points[i].cast<double>(), n = strokes_[k].normals[i].cast<double>(), d;
            if (!field(n, d)) continue;
            Vector3d side = n.cross(d);
            for (double sign : {1.0, -1.0}) tryStroke(p + sign * dsep * side, level, dsep, &n);
        }
    }

    // Traces a stroke from x when it projects onto the surface at least dsep (nearly) from every stroke.
    // `hint`: the normal near x0, for a test against the hash before x0 is projected (most seeds are refused).
    bool tryStroke(Vector3d x0, uint32_t level, double dsep, const Vector3d* hint = nullptr) {
        if (hint && hash_.near(x0, *hint, 0.8 * dsep)) return false;
        Vector3d n0, d0;
        if (!projectToSurface(hrbf_, x0, n0) || !field(n0, d0)) return false;
        if (hash_.near(x0, n0, 0.9 * dsep)) return false;
        const double dtest = o_.testRatio * dsep, gap = 3.0 * dsep;
        const uint32_t id = uint32_t(strokes_.size());
        const size_t hashStart = hash_.size();
        hash_.add(x0, n0, id, 0);
        bool closed = false;
        auto march = [&](double sign, std::vector<Vector3d>& xs, std::vector<Vector3d>& ns) {
            Vector3d x = x0, n = n0, d = sign * d0;
            double arc = 0;
            for (int k = 0; k < 20000; ++k) {
                Vector3d y = x + step_ * d, ny, dy;
                if (!stepToSurface(y, ny) || (y - x).norm() > 2 * step_ || !field(ny, dy)) return;
                if (dy.dot(d) < 0) dy = -dy;
                if (dy.dot(d) < 0.85) return;  // turns sharply: a singularity of the field is near
                arc += (y - x).norm();
                if (arc > 4 * dsep && (y - x0).norm() < 1.5 * step_) {
                    closed = sign > 0;
                    return;
                }
                if (hash_.near(y, ny, dtest, id, sign * arc, gap)) return;
                hash_.add(y, ny, id, sign * arc);
                xs.push_back(y);
                ns.push_back(ny);
                x = y, n = ny, d = dy;
            }
        };
        std::vector<Vector3d> fx, fn, bx, bn;
        march(1.0, fx, fn);
        if (!closed) march(-1.0, bx, bn);
        PenStroke s;
        s.family = family_;
        s.level = level;
        s.closed = closed;
        for (size_t i = bx.size(); i-- > 0;) {
            s.points.push_back(bx[i].cast<float>());
            s.normals.push_back(bn[i].cast<float>());
        }
        s.points.push_back(x0.cast<float>());
        s.normals.push_back(n0.cast<float>());
        for (size_t i = 0; i < fx.size(); ++i) {
            s.points.push_back(fx[i].cast<float>());
            s.normals.push_back(fn[i].cast<float>());
        }
        if (s.length() < o_.minLengthRatio * dsep) {
            hash_.truncate(hashStart);
            return false;
        }
        strokes_.push_back(std::move(s));
        return true;
    }

    // Back onto f = 0 after a step: one Newton step along ∇f is enough when the step left the surface by little
    // (the error squares: about 1e-8 of the diagonal after a step of spacing/2), else the full projection.
    bool stepToSurface(Vector3d& y, Vector3d& n) const {
        Vector3d gradient;
        double f = hrbf_.eval(y, gradient);
        double g2 = gradient.squaredNorm();
        if (!(g2 > 1e-16) || !std::isfinite(f)) return false;
        y -= (f / g2) * gradient;
        n = gradient / std::sqrt(g2);
        if (std::abs(f) < 0.05 * step_ * std::sqrt(g2)) return true;
        return projectToSurface(hrbf_, y, n);
    }

    const Surface& hrbf_;
    const std::vector<SurfaceSample>& samples_;
    const HatchOptions& o_;
    uint32_t family_;
    PointHash hash_;
    double step_;
    std::vector<PenStroke> strokes_;
};

}  // namespace

std::vector<PenStroke> traceHatching(const Surface& hrbf, const std::vector<SurfaceSample>& samples,
                                     const HatchOptions& options, HatchStats* stats) {
    auto start = std::chrono::steady_clock::now();
    const uint32_t families = std::clamp(options.families, 1u, 2u);
    std::vector<std::vector<PenStroke>> traced(families);
    std::vector<std::thread> threads;
    for (uint32_t f = 1; f < families; ++f)
        threads.emplace_back([&, f] { traced[f] = Hatcher(hrbf, samples, options, f).run(); });
    traced[0] = Hatcher(hrbf, samples, options, 0).run();
    for (std::thread& t : threads) t.join();
    std::vector<PenStroke> strokes;
    HatchStats s;
    for (auto& family : traced)
        for (PenStroke& stroke : family) {
            s.vertices += stroke.points.size();
            s.length += stroke.length();
            strokes.push_back(std::move(stroke));
        }
    s.strokes = strokes.size();
    s.seconds = secondsSince(start);
    if (stats) *stats = s;
    return strokes;
}

}  // namespace ink
