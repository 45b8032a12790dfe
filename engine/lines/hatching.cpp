// Hatching strokes (hatching.h): evenly spaced streamlines of the cross field.
#include "lines/hatching.h"
#include "shared/contour.h"

#include "base/point_hash.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

namespace ink {

using Eigen::Vector3d;

namespace {

// A stroke ends where this much of its neighbourhood is flat ground combed the other way (CrossField::flat()).
constexpr double kFlatAgainst = 0.25;

// A stroke that comes back beside its seed, going its way, within this × its separation across it, is a loop
// (a ring round a tube): it closes there. Past 2 it would meet the next ring out, not its own start.
constexpr double kLoopDrift = 1.5;

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
    Hatcher(const Surface& hrbf, const CrossField& field, const HatchOptions& o, uint32_t family)
        : hrbf_(hrbf),
          field_(field),
          o_(o),
          family_(family),
          hash_(0.9 * o.spacing * double(1u << (std::max(1u, o.levels) - 1))),
          step_(0.5 * o.spacing),
          minTurn_(std::cos(o.maxTurnDeg * M_PI / 180)) {}

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
                // The queue is empty: the next sample far enough from every stroke starts a new region, along the
                // larger principal curvature (family 0), across it (family 1) or diagonal to both (family 2).
                bool started = false;
                for (; sample < field_.size() && !started; ++sample) {
                    const Vector3d& n = field_.normals()[sample];
                    const Vector3d& d = field_.combed()[sample];
                    const Vector3d start = family_ == 0 ? d : family_ == 1 ? n.cross(d) : turned(d, n, 1.0);
                    started = tryStroke(field_.positions()[sample], start, level, dsep, &n);
                }
                if (!started) break;
            }
        }
        return std::move(strokes_);
    }

private:
    // `t` (tangent at normal n) turned by 45° about n, `sign` the way.
    static Vector3d turned(const Vector3d& t, const Vector3d& n, double sign) {
        return (t + sign * n.cross(t)) * std::sqrt(0.5);
    }

    // The field's direction at x (normal n) nearest `reference`; false near a singularity. The diagonal family
    // follows the cross field turned by 45° (itself a cross field): the reference is turned back, matched to the
    // field's four directions, and the match turned forward.
    bool field(const Vector3d& x, const Vector3d& n, const Vector3d& reference, Vector3d& d) const {
        double coherence = 0;
        Eigen::Vector2d comb;
        const Vector3d ref = reference - reference.dot(n) * n, back = family_ < 2 ? ref : turned(ref, n, -1.0);
        if (!field_.lookup(x, n, back, d, &coherence, &comb) || coherence < o_.minCoherence) return false;
        // On flat ground a stroke keeps to its family's direction there (`comb`: (1, 0) along the flat comb, (−1, 0)
        // across it): one coming off a curved part in the other family's direction ends at its edge.
        if ((family_ == 1 ? -comb.x() : comb.x()) < -kFlatAgainst) return false;
        if (family_ == 2) d = turned(d, n, 1.0);
        return true;
    }

    // Seeds at the separation on both sides of stroke k, each along the stroke's own direction there (tracing
    // appends to strokes_: no references into it).
    void seedBeside(size_t k, uint32_t level, double dsep) {
        const size_t m = strokes_[k].points.size();
        for (size_t i = 0; i < m; i += 2) {
            const Vector3d p = strokes_[k].points[i].cast<double>(), n = strokes_[k].normals[i].cast<double>();
            const Vector3d t =
                (strokes_[k].points[std::min(i + 1, m - 1)] - strokes_[k].points[i > 0 ? i - 1 : 0]).cast<double>();
            Vector3d side = n.cross(t);
            if (!(side.norm() > 1e-12)) continue;
            side.normalize();
            for (double sign : {1.0, -1.0}) tryStroke(p + sign * dsep * side, t, level, dsep, &n);
        }
    }

    // Traces a stroke from x0 along the field's direction nearest `reference` when x0 projects onto the surface at
    // least dsep (nearly) from every stroke. `hint`: the normal near x0, for a test against the hash before x0 is
    // projected (most seeds are refused).
    bool tryStroke(Vector3d x0, const Vector3d& reference, uint32_t level, double dsep, const Vector3d* hint) {
        if (hint && hash_.near(x0, *hint, 0.8 * dsep)) return false;
        Vector3d n0, d0;
        if (!projectToSurface(hrbf_, x0, n0) || !field(x0, n0, reference, d0)) return false;
        if (hash_.near(x0, n0, 0.9 * dsep)) return false;
        const double dtest = o_.testRatio * dsep, gap = 3.0 * dsep;
        const uint32_t id = uint32_t(strokes_.size());
        const size_t hashStart = hash_.size();
        hash_.add(x0, n0, id, 0);
        bool closed = false;
        Vector3d drift = Vector3d::Zero();  // a closed loop's offset from its seed where it came back (kLoopDrift)
        std::vector<double> arcs;           // of the forward points
        auto march = [&](double sign, std::vector<Vector3d>& xs, std::vector<Vector3d>& ns) {
            Vector3d x = x0, d = sign * d0;
            double arc = 0;
            for (int k = 0; k < 20000; ++k) {
                Vector3d y = x + step_ * d, ny, dy;
                // A step the projection sends back beside where it began goes nowhere (as the contour's
                // CONTOUR_LEAST_PROGRESS): the stroke ends rather than piling points on one spot.
                if (!stepToSurface(y, ny) || (y - x).norm() > 2 * step_ ||
                    (y - x).norm() < gpu::CONTOUR_LEAST_PROGRESS * step_ || !field(y, ny, d, dy))
                    return;
                if (dy.dot(d) < minTurn_) return;  // turns sharply
                arc += (y - x).norm();
                if (sign > 0 && arc > 4 * dsep && dy.dot(d0) > 0.7) {
                    // Back beside its seed, going its way: a loop (a ring round a tube). The field's small errors
                    // bring it back off its seed by a drift across it; it closes there, the drift spread over its
                    // second half (below), rather than ending on itself with a jog.
                    const Vector3d back = x0 - y;
                    const double along = back.dot(dy);
                    const Vector3d across = back - along * dy;
                    if (along > -0.5 * step_ && along < 1.5 * step_ && across.norm() < kLoopDrift * dsep) {
                        closed = true;
                        drift = across;
                        return;
                    }
                }
                if (hash_.near(y, ny, dtest, id, sign * arc, gap)) return;
                hash_.add(y, ny, id, sign * arc);
                xs.push_back(y);
                ns.push_back(ny);
                if (sign > 0) arcs.push_back(arc);
                x = y, d = dy;
            }
        };
        std::vector<Vector3d> fx, fn, bx, bn;
        march(1.0, fx, fn);
        if (!closed) march(-1.0, bx, bn);
        if (closed && drift.squaredNorm() > 0 && !arcs.empty()) {
            // The loop's second half moved across by up to the drift, growing linearly, and back onto the surface;
            // its entries in the hash again where they now lie.
            const double half = 0.5 * arcs.back();
            hash_.truncate(hashStart + 1);
            for (size_t i = 0; i < fx.size(); ++i) {
                const double w = std::clamp((arcs[i] - half) / half, 0.0, 1.0);
                if (w > 0) {
                    Vector3d y = fx[i] + w * drift, ny;
                    if (projectToSurface(hrbf_, y, ny)) fx[i] = y, fn[i] = ny;
                }
                hash_.add(fx[i], fn[i], id, arcs[i]);
            }
        }
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
    const CrossField& field_;
    const HatchOptions& o_;
    uint32_t family_;
    PointHash hash_;
    double step_, minTurn_;
    std::vector<PenStroke> strokes_;
};

}  // namespace

std::vector<PenStroke> traceHatching(const Surface& hrbf, const CrossField& field, const HatchOptions& options,
                                     HatchStats* stats) {
    auto start = std::chrono::steady_clock::now();
    const uint32_t families = std::clamp(options.families, 1u, kMaxHatchFamilies);
    std::vector<std::vector<PenStroke>> traced(families);
    std::vector<std::thread> threads;
    for (uint32_t f = 1; f < families; ++f)
        threads.emplace_back([&, f] { traced[f] = Hatcher(hrbf, field, options, f).run(); });
    traced[0] = Hatcher(hrbf, field, options, 0).run();
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

std::vector<PenStroke> traceHatching(const Surface& hrbf, const std::vector<SurfaceSample>& samples,
                                     const HatchOptions& options, HatchStats* stats) {
    auto start = std::chrono::steady_clock::now();
    const CrossField field(hrbf, samples, options.field);
    const double fieldSeconds = secondsSince(start);
    std::vector<PenStroke> strokes = traceHatching(hrbf, field, options, stats);
    if (stats) {
        stats->fieldSeconds = fieldSeconds;
        stats->seconds = secondsSince(start);
    }
    return strokes;
}

}  // namespace ink
