// Contour strokes (lines.h), traced on the CPU in object space.
#include "lines/lines.h"

#include "base/common.h"
#include "base/point_hash.h"
#include "shared/contour.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <queue>
#include <thread>
#include <tuple>
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

// Newton on (f, g) = 0 with the minimum-norm step of the 2×3 system, done when a step moves less than
// kNewtonDone (normalized units: a thousandth of a pixel at 1024²; convergence is quadratic, so the error left is
// about the curvature times its square, ~1e-10). The step after the predictor's correction is ~1e-7 (the bunny's
// median): most points take two evaluations, not three. `last` gets the evaluation of the last iteration, taken
// within kNewtonDone of the point returned: the next step's tangent.
constexpr double kNewtonDone = 1e-6;

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
        if (dx.norm() < kNewtonDone) return true;
    }
    return false;
}

}  // namespace

bool projectToContour(const Surface& hrbf, const Vector3d& eye, Vector3d& x) {
    return contourNewton(hrbf, eye, x, 0.05);
}

// The view angle of one segment: the chord between its ends' directions from the eye.
static double segmentAngle(const Vector3d& a, const Vector3d& b, const Vector3d& eye) {
    return ((b - eye).normalized() - (a - eye).normalized()).norm();
}

double viewAngle(const std::vector<Vector3d>& curve, const Vector3d& eye, bool closed) {
    const size_t m = curve.size();
    double angle = 0;
    for (size_t i = 0; i + (closed ? 0 : 1) < m; ++i) angle += segmentAngle(curve[i], curve[(i + 1) % m], eye);
    return angle;
}

bool droppedLoop(const std::vector<Vector3d>& curve, bool closed, const Vector3d& eye, const ContourOptions& options) {
    if (curve.size() < 4) return true;
    if (!closed) return false;
    double length = 0;
    for (size_t i = 1; i < curve.size(); ++i) length += (curve[i] - curve[i - 1]).norm();
    return length < options.minLoopLength || viewAngle(curve, eye, true) < options.minLoopAngle;
}

// Swallowtails too small to see: a pair of cusps whose retrograde piece between them spans less than
// `threshold` of view angle (a ripple of the normal field, not the shape) is no cusp at all. The pair goes,
// smallest first, and the pieces either side join: their view angles add. A heap and a linked list keep it
// O(c log c) in the cusps and O(m) in the vertices, however rough the surface. Returns the pairs removed.
static size_t mergeSwallowtails(const std::vector<Vector3d>& curve, const Vector3d& eye, bool closed, double threshold,
                                std::vector<size_t>& cusps) {
    const size_t c = cusps.size(), m = curve.size();
    if (c < 2) return 0;
    constexpr size_t kNone = SIZE_MAX;
    // Cusp k's piece runs to cusp next[k] (none past an open curve's last cusp); angle[k] is its view angle.
    std::vector<size_t> prev(c), next(c);
    std::vector<double> angle(c, 0.0);
    std::vector<uint32_t> version(c, 0);
    std::vector<bool> gone(c, false);
    for (size_t k = 0; k < c; ++k) {
        prev[k] = k > 0 ? k - 1 : (closed ? c - 1 : kNone);
        next[k] = k + 1 < c ? k + 1 : (closed ? 0 : kNone);
        if (next[k] == kNone) continue;
        for (size_t i = cusps[k]; i != cusps[next[k]]; i = (i + 1) % m)
            angle[k] += segmentAngle(curve[i], curve[(i + 1) % m], eye);
    }
    using Entry = std::tuple<double, size_t, uint32_t>;  // angle, cusp, version
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (size_t k = 0; k < c; ++k)
        if (next[k] != kNone && angle[k] < threshold) heap.push({angle[k], k, 0});
    size_t left = c, merged = 0;
    while (!heap.empty() && left >= 2) {
        const auto [a, k, v] = heap.top();
        heap.pop();
        if (gone[k] || v != version[k] || next[k] == kNone) continue;
        const size_t j = next[k], p = prev[k], q = next[j];
        gone[k] = gone[j] = true;
        left -= 2;
        ++merged;
        if (left == 0) break;
        // The piece from p (or the curve's start) now runs past k and j to q (or the curve's end).
        if (p != kNone) {
            next[p] = q;
            if (q != kNone) angle[p] += angle[k] + angle[j];
            ++version[p];
            if (q != kNone && left >= 2 && angle[p] < threshold) heap.push({angle[p], p, version[p]});
        }
        if (q != kNone) prev[q] = p;
    }
    std::vector<size_t> kept;
    for (size_t k = 0; k < c; ++k)
        if (!gone[k]) kept.push_back(cusps[k]);
    cusps = std::move(kept);
    return merged;
}

void splitAtCusps(const std::vector<Vector3d>& curve, const std::vector<Vector3d>& normals, bool closed,
                  const Vector3d& eye, const ContourOptions& options, uint32_t curveId, std::vector<PenStroke>& pieces,
                  ContourStats& s) {
    // The cusps: where the image of the curve reverses, i.e. the tangent's component along w = n × v (the tangent
    // plane's direction across the view ray) changes sign.
    const size_t m = curve.size();
    std::vector<double> across(m);
    for (size_t i = 0; i < m; ++i) {
        size_t prev = i > 0 ? i - 1 : (closed ? m - 1 : i), next = i + 1 < m ? i + 1 : (closed ? 0 : i);
        Vector3d t = curve[next] - curve[prev];
        across[i] = t.dot(normals[i].cross((curve[i] - eye).normalized()));
    }
    std::vector<size_t> cusps;
    for (size_t i = 0; i + (closed ? 0 : 1) < m; ++i) {
        size_t j = (i + 1) % m;
        if ((across[i] < 0) != (across[j] < 0)) cusps.push_back(std::abs(across[i]) < std::abs(across[j]) ? i : j);
    }
    s.swallowtails += mergeSwallowtails(curve, eye, closed, options.minSwallowtail, cusps);
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
}

size_t markOccluded(const Surface& hrbf, const Vector3d& eye, double minLength, std::vector<PenStroke>& pieces) {
    constexpr double kFlatRadial = 0.5;
    size_t count = 0;
    for (PenStroke& p : pieces) {
        const size_t m = p.points.size();
        if (p.length() < minLength) continue;
        int votes = 0;
        for (size_t k = 1; k <= 5 && m > 0; ++k) {
            const Vector3d x = p.points[std::min(m - 1, m * k / 6)].cast<double>();
            Vector3d g;
            Eigen::Matrix3d h;
            hrbf.eval(x, g, &h);
            if (!(g.norm() > 0)) continue;
            const Vector3d n = g.normalized();
            Vector3d r = (eye - x).normalized();
            r -= r.dot(n) * n;  // on the contour n·v = 0: the view ray's direction in the tangent plane
            if (!(r.norm() > 1e-9)) continue;
            r.normalize();
            // κ_r, normalized units (the diagonal is 1): where the surface is nearly flat along the view (a
            // radius of curvature over two diagonals) the fit's noise would decide, and the point abstains.
            const double radial = r.dot(h * r) / g.norm();
            if (std::isfinite(radial) && std::abs(radial) > kFlatRadial) votes += radial < 0 ? 1 : -1;
        }
        p.occluded = votes > 0;
        count += p.occluded;
    }
    return count;
}

// An extension closes a gap the device left: a stretch of a few nodes' spacing, not a whole curve.
constexpr uint32_t kMaxExtension = 4096;

std::vector<Vector3d> extendContour(const Surface& hrbf, const Vector3d& eye, const Vector3d& start,
                                    const Vector3d& direction, PointHash& traced, uint32_t curve, double arcAtStart,
                                    double arcSign, const ContourOptions& options) {
    std::vector<Vector3d> out;
    const double step = options.step;
    Vector3d x = start;
    ContourEval e = evalContour(hrbf, eye, x), next;
    Vector3d previous = direction.normalized();
    double h = step, arc = 0;
    for (uint32_t k = 0; k < kMaxExtension; ++k) {
        Vector3d t = e.gradF.cross(e.gradG);
        if (!(t.norm() > 1e-12 * e.gradF.norm() * e.gradG.norm())) break;
        t.normalize();
        if (t.dot(previous) < 0) t = -t;
        Vector3d y = x + h * t;
        if (!contourNewton(hrbf, eye, y, 2 * h, 10, &next) || (y - x).norm() < gpu::CONTOUR_LEAST_PROGRESS * h) {
            if (h <= step / 16) break;
            h *= 0.5;
            continue;
        }
        double turn = std::acos(std::clamp(t.dot(previous), -1.0, 1.0));
        if (turn > 0.15)
            h = std::max(step / 16, h * 0.5);
        else if (turn < 0.05)
            h = std::min(2 * step, h * 1.5);
        arc += (y - x).norm();
        out.push_back(y);
        // Reached a traced curve: another one, or its own beyond the stretch it leaves from.
        const Vector3d n = e.gradF.normalized();
        if (traced.near(y, n, 0.5 * step, curve, arcAtStart + arcSign * arc, 6 * step)) break;
        traced.add(y, n, curve, arcAtStart + arcSign * arc);
        previous = t;
        x = y;
        e = next;
    }
    return out;
}

std::vector<PenStroke> keepRuns(const std::vector<PenStroke>& strokes, const std::function<bool(size_t, size_t)>& keep,
                                size_t* dropped) {
    std::vector<PenStroke> out;
    size_t removed = 0;
    for (size_t si = 0; si < strokes.size(); ++si) {
        const PenStroke& s = strokes[si];
        const size_t m = s.points.size();
        std::vector<bool> in(m);
        size_t kept = 0;
        for (size_t i = 0; i < m; ++i) kept += in[i] = keep(si, i);
        removed += m - kept;
        if (kept == m) {
            out.push_back(s);
            continue;
        }
        // A closed stroke cut open starts after its first cut, so that its run across the start stays whole.
        size_t start = 0;
        if (s.closed)
            while (start < m && in[start]) ++start;
        PenStroke run;
        auto flush = [&] {
            if (run.points.size() >= 2) out.push_back(std::move(run));
            run = {};
        };
        for (size_t k = 0; k < m; ++k) {
            const size_t i = (start + k) % m;
            if (!in[i]) {
                flush();
                continue;
            }
            run.points.push_back(s.points[i]);
            run.normals.push_back(s.normals[i]);
            if (!s.standoff.empty()) run.standoff.push_back(s.standoff[i]);
            run.curve = s.curve;
            run.family = s.family;
            run.level = s.level;
            run.occluded = s.occluded;
            run.faced = s.faced;
        }
        flush();
    }
    if (dropped) *dropped = removed;
    return out;
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
        // Each vertex's unit normal is taken from the corrector's last evaluation (within kNewtonDone of it).
        std::vector<Vector3d> forward, backward, forwardNormals, backwardNormals;
        bool closed = false;
        const size_t hashStart = traced.size();
        auto march = [&](double sign, std::vector<Vector3d>& out, std::vector<Vector3d>& outNormals) {
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
                if (!contourNewton(hrbf, eye, y, 2 * h, 10, &next) ||
                    (y - x).norm() < gpu::CONTOUR_LEAST_PROGRESS * h) {
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
                outNormals.push_back(next.gradF.normalized());
                previous = t;
                x = y;
                e = next;
            }
        };
        march(1.0, forward, forwardNormals);
        if (!closed) march(-1.0, backward, backwardNormals);
        std::vector<Vector3d> curve(backward.rbegin(), backward.rend());
        curve.push_back(x0);
        curve.insert(curve.end(), forward.begin(), forward.end());
        // Closed only where its ends meet: a backward march that came back near the seed after the forward one
        // stopped elsewhere (a small loop at the seed, a branch passing it) left the forward march's end far from
        // its start, and the closing segment bridged them (CGAL's elephant-with-holes from behind: across the paper
        // from the trunk to the rump).
        closed = closed && (curve.back() - curve.front()).norm() <= 5 * step;
        if (droppedLoop(curve, closed, eye, options)) {
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

        std::vector<Vector3d> normals(backwardNormals.rbegin(), backwardNormals.rend());
        Vector3d gradient;
        hrbf.eval(x0, gradient);
        normals.push_back(gradient.normalized());
        normals.insert(normals.end(), forwardNormals.begin(), forwardNormals.end());
        splitAtCusps(curve, normals, closed, eye, options, curveId, pieces, s);
        ++curveId;
    }
    s.pieces = pieces.size();
    s.occluded = markOccluded(hrbf, eye, kOccludedSteps * options.step, pieces);
    s.seconds = secondsSince(start);
    if (stats) *stats = s;
    return pieces;
}

}  // namespace ink
