// Pen lines (lines.h): the traced occluding contour of a fitted torus against the analytic one, and hatching.
#include "base/image.h"
#include "base/point_hash.h"
#include "draw/camera.h"
#include "draw/renderer.h"
#include "draw/scene.h"
#include "gpu_fixture.h"
#include "lines/contour_device.h"
#include "lines/lines.h"
#include "run_command.h"
#include "skip.h"
#include "surface/model.h"
#include "surface/shapes.h"
#include "temp_dir.h"
#include "torus_fixture.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/glm.hpp>
#include <map>
#include <set>
#include <sstream>

using Eigen::Vector3d;

using namespace torus_fixture;

namespace {

struct Projector {
    glm::mat4 viewProjection;
    double size;
    Eigen::Vector2d operator()(const Vector3d& x) const {
        glm::vec4 c = viewProjection * glm::vec4(float(x.x()), float(x.y()), float(x.z()), 1.0f);
        return {(c.x / c.w * 0.5 + 0.5) * size, (c.y / c.w * 0.5 + 0.5) * size};
    }
};

// The outer boundary of a set of image points as the largest radius about `centre` in each of `bins` angles.
struct Outline {
    Eigen::Vector2d centre;
    std::vector<double> radius;
    std::vector<int> owner;  // which polyline gave the largest radius
    Outline(Eigen::Vector2d c, int bins) : centre(c), radius(bins, -1.0), owner(bins, -1) {}
    void add(const Eigen::Vector2d& p, int who) {
        Eigen::Vector2d d = p - centre;
        int bin = int(std::floor((std::atan2(d.y(), d.x()) + M_PI) / (2 * M_PI) * double(radius.size())));
        bin = std::clamp(bin, 0, int(radius.size()) - 1);
        if (d.norm() > radius[bin]) radius[bin] = d.norm(), owner[bin] = who;
    }
};

// The contour tracer's seeds: the fit's control points with their normals.
std::vector<ink::SurfaceSample> seedsOf(const ink::Model& m) {
    std::vector<ink::SurfaceSample> seeds;
    for (size_t i = 0; i < m.surface.size(); ++i) seeds.push_back({m.surface.centers[i], m.surface.normals[i]});
    return seeds;
}

}  // namespace

// The contour's cusps and vertices of a model fitted with default options, seen by the default camera.
ink::ContourStats contourOf(const ink::Model& m, float azimuth, float elevation) {
    ink::Camera camera;
    camera.azimuthDeg = azimuth;
    camera.elevationDeg = elevation;
    const glm::vec3 e = camera.eye();
    ink::ContourStats stats;
    ink::traceContours(m.surface, Vector3d(e.x, e.y, e.z), seedsOf(m), {}, &stats);
    return stats;
}

namespace {

// tests/models/plate-with-hole.obj ([-1, 1]² × [-0.3, 0.3], a hole of radius 0.4 along z) from 30° above.
ink::Camera plateCamera(float azimuth) {
    ink::Camera camera;
    camera.up = ink::UpAxis::PosZ;
    camera.azimuthDeg = azimuth;
    camera.elevationDeg = 30;
    return camera;
}

// The plate's contour pieces that run down its hole's wall from rim to rim, and how many of them are occluded.
size_t holeWallPieces(const ink::Model& plate, const std::vector<ink::PenStroke>& pieces, size_t& occluded) {
    size_t wall = 0;
    occluded = 0;
    for (const ink::PenStroke& p : pieces) {
        size_t onWall = 0;
        double low = 1, high = -1;
        for (const Eigen::Vector3f& x : p.points) {
            const Vector3d q = plate.surface.frame.toInput(x.cast<double>());
            onWall += std::abs(std::hypot(q.x(), q.y()) - 0.4) < 0.03;
            low = std::min(low, q.z()), high = std::max(high, q.z());
        }
        if (onWall == p.points.size() && high - low > 0.4) ++wall, occluded += p.occluded;
    }
    return wall;
}

}  // namespace

TEST_CASE("contours: fitted meshes have their true cusps only (issue 24)" * doctest::test_suite("unit")) {
    // A 64 × 32 torus mesh of 2,048 vertices: its contour has no cusp at these views; the fit to its vertices and
    // all its flat face samples gave 21,906 cusps and 409,614 vertices (65 s).
    TempDir dir;
    torus_fixture::writeTorusMesh(dir / "torus.obj");
    const ink::Model torusMesh = ink::loadModel(dir / "torus.obj", {});
    for (float elevation : {20.0f, 60.0f}) {
        CAPTURE(elevation);
        ink::ContourStats s = contourOf(torusMesh, 30, elevation);
        CHECK(s.cusps <= 4);
        CHECK(s.curves >= 1);
        CHECK(s.curves <= 4);
        CHECK(s.vertices < 3000);
    }
    // The bunny (1,839 vertices): 42 cusps and 2,313 vertices measured (34,203 and 916,832 before).
    const ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {});
    ink::ContourStats s = contourOf(bunny, 0, 15);
    CHECK(s.cusps <= 100);
    CHECK(s.vertices <= 20000);
    CHECK(s.curves >= 3);
}

// Koenderink (1984): where the surface is concave along the view, its contour lies behind the surface beside it.
// A drilled hole's wall is such a place: seen from above, its contour is the two generators at the ends of the
// hole, which the depth test let show as ticks below the rim (its four push-backs reach past the rounded rim).
TEST_CASE("contours: the pieces a hole's own wall hides are marked so, the outline's are not" *
          doctest::test_suite("unit")) {
    const ink::Model plate = ink::loadModel(INKWELL_SOURCE_DIR "/tests/models/plate-with-hole.obj", {});
    for (const float azimuth : {30.0f, 135.0f, 200.0f}) {
        CAPTURE(azimuth);
        const glm::vec3 e = plateCamera(azimuth).eye();
        ink::ContourStats stats;
        const std::vector<ink::PenStroke> pieces =
            ink::traceContours(plate.surface, Vector3d(e.x, e.y, e.z), seedsOf(plate), {}, &stats);
        // A piece down the wall from rim to rim is hidden; the longest, around the outer faces, is not (where the
        // fit's rounded vertical edges ripple it turns in and out in short pieces, which the depth test judges).
        size_t wallHidden = 0;
        const size_t wall = holeWallPieces(plate, pieces, wallHidden);
        const ink::PenStroke* longest = nullptr;
        for (const ink::PenStroke& p : pieces)
            if (!longest || p.length() > longest->length()) longest = &p;
        REQUIRE(longest);
        MESSAGE("azimuth " << azimuth << ": " << pieces.size() << " pieces, " << stats.occluded << " occluded; on the "
                           << "hole's wall " << wallHidden << " of " << wall << "; the longest " << longest->length());
        CHECK(wall == 2);
        CHECK(wallHidden == wall);
        CHECK(longest->length() > 2.0);
        CHECK_FALSE(longest->occluded);
    }
}

// The same marks when the device traces the contour (a GPU's default, autoOnDevice; lavapipe traces on the CPU).
TEST_CASE("contours: traced on the device, the pieces a hole's own wall hides are marked so too" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::LineOptions lines;
    lines.contours = true;
    lines.contourTracer = ink::LineOptions::ContourTracer::Device;
    ink::RefineOptions refine;
    refine.levels = 3;
    ink::Scene scene(gpu.ctx, ink::loadModel(INKWELL_SOURCE_DIR "/tests/models/plate-with-hole.obj", {}),
                     ink::DrawStyle::Stipple, refine, lines);
    scene.traceContours(plateCamera(30));
    REQUIRE(scene.contourStats.onDevice);
    size_t wallHidden = 0;
    const size_t wall = holeWallPieces(scene.model, scene.contours, wallHidden);
    MESSAGE("device: " << scene.contours.size() << " pieces, " << scene.contourStats.occluded << " occluded, on the "
                       << "hole's wall " << wallHidden << " of " << wall);
    CHECK(wall == 2);
    CHECK(wallHidden == wall);
    gpu.requireNoValidationErrors();
}

TEST_CASE("contours: a march the corrector holds in place stops there, without piling up vertices" *
          doctest::test_suite("unit")) {
    // Seen from 291.8° (a frame of `bench`'s orbit), the bunny's contour runs into a point where each corrected
    // step lands back beside the last, the steps shrinking geometrically: the march from this seed made 100,000
    // vertices on one spot and took 20 s. A step that makes less than a quarter of its length counts as rejected.
    const ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {});
    ink::Camera camera;
    camera.azimuthDeg = 30.0f + 360.0f * 8.0f / 11.0f;
    const glm::vec3 e = camera.eye();
    const Vector3d eye(e.x, e.y, e.z), x(-0.191884, -0.198829, 0.0388608);
    Vector3d gradient;
    bunny.surface.eval(x, gradient);
    // The curve from this seed is a small loop in the image, which the tracer drops (minLoopAngle): kept here, to
    // see its vertices.
    ink::ContourOptions options;
    options.minLoopAngle = 0;
    ink::ContourStats stats;
    const std::vector<ink::PenStroke> pieces =
        ink::traceContours(bunny.surface, eye, {{x, gradient.normalized()}}, options, &stats);
    CHECK(stats.curves == 1);
    CHECK(stats.vertices < 2000);
    double shortest = 1;
    for (const ink::PenStroke& p : pieces)
        for (size_t i = 1; i < p.points.size(); ++i)
            shortest = std::min(shortest, double((p.points[i] - p.points[i - 1]).norm()));
    CHECK(shortest > ink::ContourOptions{}.step / 16 * 0.2);
}

TEST_CASE("contours: swallowtails smaller than the pen are no cusps; the pieces either side join" *
          doctest::test_suite("unit")) {
    // The bunny from its first picture (330°, 15°): its fit's ripples fold the contour's image into tiny
    // swallowtails, each a pair of cusps a few pixels apart.
    const ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {});
    ink::Camera camera;
    camera.azimuthDeg = 330;
    camera.elevationDeg = 15;
    const glm::vec3 e = camera.eye();
    const std::vector<ink::SurfaceSample> seeds = seedsOf(bunny);
    auto trace = [&](double minSwallowtail, ink::ContourStats& stats) {
        ink::ContourOptions options;
        options.minSwallowtail = minSwallowtail;
        return ink::traceContours(bunny.surface, Vector3d(e.x, e.y, e.z), seeds, options, &stats);
    };
    ink::ContourStats raw, merged, all;
    const std::vector<ink::PenStroke> rawPieces = trace(0.0, raw);
    const std::vector<ink::PenStroke> pieces = trace(ink::ContourOptions{}.minSwallowtail, merged);
    trace(10.0, all);  // every pair merges: at most one cusp a curve is left
    MESSAGE("bunny contour: " << raw.cusps << " cusps, " << merged.swallowtails << " swallowtails under "
                              << ink::ContourOptions{}.minSwallowtail << " rad merged, " << merged.cusps << " left");
    CHECK(raw.swallowtails == 0);
    CHECK(merged.swallowtails > 0);
    CHECK(merged.cusps + 2 * merged.swallowtails == raw.cusps);
    CHECK(all.cusps <= all.curves);
    // The same curves and vertices, in fewer pieces: each merged pair joins three pieces into one (two into a
    // closed one where a closed curve's last pair goes).
    CHECK(merged.vertices == raw.vertices);
    CHECK(merged.curves == raw.curves);
    CHECK(pieces.size() + 2 * merged.swallowtails >= rawPieces.size());
    CHECK(pieces.size() + merged.swallowtails <= rawPieces.size());
    size_t rawPoints = 0, points = 0;
    for (const ink::PenStroke& p : rawPieces) rawPoints += p.points.size();
    for (const ink::PenStroke& p : pieces) points += p.points.size();
    CHECK(points < rawPoints);  // a piece shares its end point with the next: fewer pieces, fewer shared points
    CHECK(points + 2 * merged.swallowtails + merged.curves >= rawPoints);
}

TEST_CASE("contours: closed curves too small in the image to read are dropped, the rest kept" *
          doctest::test_suite("unit")) {
    // The bunny's fit makes small lips here and there: closed contour curves long along the view but a few pixels
    // across in the image (beside its front foot at the default view), which the pen drew as dashes and blots.
    const ink::Model bunny = ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {});
    const std::vector<ink::SurfaceSample> seeds = seedsOf(bunny);
    const double minAngle = ink::ContourOptions{}.minLoopAngle;
    size_t smallRaw = 0, droppedMore = 0;
    for (float azimuth : {0.0f, 30.0f, 90.0f, 150.0f, 210.0f, 270.0f, 330.0f}) {
        CAPTURE(azimuth);
        ink::Camera camera;
        camera.azimuthDeg = azimuth;
        const glm::vec3 e = camera.eye();
        const Vector3d eye(e.x, e.y, e.z);
        // The view angle each curve sweeps (its pieces' together, in order), by curve, and whether it is closed (its
        // last piece ends where its first begins).
        struct Curve {
            double angle = 0;
            bool closed = false;
            Eigen::Vector3f start;
        };
        auto curvesOf = [&](double minLoopAngle, ink::ContourStats& stats) {
            ink::ContourOptions options;
            options.minLoopAngle = minLoopAngle;
            const std::vector<ink::PenStroke> pieces = ink::traceContours(bunny.surface, eye, seeds, options, &stats);
            std::map<uint32_t, Curve> curves;
            for (const ink::PenStroke& p : pieces) {
                std::vector<Vector3d> points;
                for (const Eigen::Vector3f& q : p.points) points.push_back(q.cast<double>());
                auto [it, first] = curves.try_emplace(p.curve);
                if (first) it->second.start = p.points.front();
                it->second.angle += ink::viewAngle(points, eye, p.closed);
                it->second.closed = p.closed || p.points.back() == it->second.start;
            }
            return curves;
        };
        ink::ContourStats rawStats, stats;
        const std::map<uint32_t, Curve> raw = curvesOf(0.0, rawStats), kept = curvesOf(minAngle, stats);
        double rawLarge = 0, keptLarge = 0, smallest = 1e9;
        for (const auto& [id, c] : raw) {
            smallRaw += c.closed && c.angle < minAngle;
            if (c.angle >= 2 * minAngle) rawLarge += c.angle;
        }
        for (const auto& [id, c] : kept) {
            if (c.closed) smallest = std::min(smallest, c.angle);
            if (c.angle >= 2 * minAngle) keptLarge += c.angle;
        }
        MESSAGE("azimuth " << azimuth << ": " << rawStats.curves << " curves, " << stats.curves << " kept ("
                           << stats.smallLoops - rawStats.smallLoops << " more dropped), the smallest closed one kept "
                           << smallest << " rad; the larger curves sweep " << rawLarge << " and " << keptLarge);
        droppedMore += stats.smallLoops - rawStats.smallLoops;
        CHECK(smallest >= minAngle);
        CHECK(stats.curves <= rawStats.curves);
        CHECK(keptLarge == doctest::Approx(rawLarge).epsilon(0.01));
    }
    CHECK(smallRaw > 0);
    CHECK(droppedMore >= smallRaw);
}

TEST_CASE("contours: the torus's traced outer silhouette lies within a pixel of the analytic one, in few pieces" *
          doctest::test_suite("unit")) {
    const ink::Model& m = torus();
    const double scale = m.surface.frame.scale;
    const Vector3d centre = m.surface.frame.toNormalized(Vector3d::Zero());
    for (float elevation : {15.0f, 50.0f}) {
        CAPTURE(elevation);
        ink::Camera camera;
        camera.elevationDeg = elevation;
        glm::vec3 eyeF = camera.eye();
        const Vector3d eye(eyeF.x, eyeF.y, eyeF.z);
        ink::ContourStats stats;
        std::vector<ink::PenStroke> pieces = ink::traceContours(m.surface, eye, torusSamples(m, 96, 32), {}, &stats);
        REQUIRE(!pieces.empty());
        // Every traced point is on both equations.
        for (const ink::PenStroke& s : pieces)
            for (const Eigen::Vector3f& p : s.points) {
                Vector3d x = p.cast<double>(), g;
                double f = m.surface.eval(x, g);
                CHECK(std::abs(f) / g.norm() < 1e-6);
                CHECK(std::abs(g.normalized().dot((x - eye).normalized())) < 1e-4);
            }
        // Every traced curve closed, each in at most 4 pieces (cut at cusps), and no curve was traced twice: a torus
        // has at most 2 contour curves seen from outside its hole's axis.
        std::map<uint32_t, int> piecesOfCurve;
        for (const ink::PenStroke& s : pieces) ++piecesOfCurve[s.curve];
        CHECK(stats.closedCurves == stats.curves);
        CHECK(stats.curves <= 2);
        for (auto [curve, count] : piecesOfCurve) CHECK(count <= 4);

        const double size = 1024;
        Projector project{camera.projection(1.0f) * camera.view(), size};
        // The analytic contour: per meridian angle u, the roots in v of n(u, v)·(q(u, v) − eye) = 0, normalized.
        Outline analytic(project(centre), 2048), traced(project(centre), 2048);
        auto point = [&](double u, double v, Vector3d* normal = nullptr) {
            Vector3d c(std::cos(u), std::sin(u), 0), n = std::cos(v) * c + std::sin(v) * Vector3d::UnitZ();
            if (normal) *normal = n;
            return Vector3d(centre + scale * (kR * c + kr * n));
        };
        auto g = [&](double u, double v) {
            Vector3d n, q = point(u, v, &n);
            return n.dot(q - eye);
        };
        const int nu = 8192, nv = 256;
        for (int i = 0; i < nu; ++i) {
            double u = 2 * M_PI * i / nu;
            for (int j = 0; j < nv; ++j) {
                double v0 = 2 * M_PI * j / nv, v1 = 2 * M_PI * (j + 1) / nv;
                if ((g(u, v0) < 0) == (g(u, v1) < 0)) continue;
                for (int k = 0; k < 40; ++k) {
                    double mid = 0.5 * (v0 + v1);
                    ((g(u, mid) < 0) == (g(u, v0) < 0) ? v0 : v1) = mid;
                }
                analytic.add(project(point(u, 0.5 * (v0 + v1))), 0);
            }
        }
        for (size_t k = 0; k < pieces.size(); ++k) {
            const auto& pts = pieces[k].points;
            size_t segments = pts.size() - 1 + (pieces[k].closed ? 1 : 0);
            for (size_t i = 0; i < segments; ++i) {
                Eigen::Vector2d a = project(pts[i].cast<double>()),
                                b = project(pts[(i + 1) % pts.size()].cast<double>());
                int steps = std::max(1, int(std::ceil((b - a).norm() / 0.25)));
                for (int t = 0; t <= steps; ++t) traced.add(a + (b - a) * (double(t) / steps), int(k));
            }
        }
        size_t within = 0, bins = 0;
        std::set<int> outerPieces;
        for (size_t b = 0; b < analytic.radius.size(); ++b) {
            if (analytic.radius[b] < 0) continue;
            ++bins;
            if (traced.radius[b] >= 0 && std::abs(traced.radius[b] - analytic.radius[b]) <= 1.0) ++within;
            if (traced.owner[b] >= 0) outerPieces.insert(traced.owner[b]);
        }
        CHECK(bins > 2000 * 0.99);
        CHECK(double(within) >= 0.99 * double(bins));
        CHECK(outerPieces.size() <= 4);
        MESSAGE("elevation " << elevation << ": " << stats.curves << " curves, " << pieces.size() << " pieces, "
                             << stats.cusps << " cusps, " << stats.vertices << " vertices, " << within << "/" << bins
                             << " bins within 1 px, " << stats.seconds * 1000 << " ms");
    }
}

// ---- On the device ----------------------------------------------------------------------------------------------

namespace {

// Distance from p to segment ab.
double segmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
    Vector3d d = b - a;
    double t = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
    return (p - (a + t * d)).norm();
}

// For points along the strokes, the distance to the nearest other stroke of the same family on the same side of
// the surface: the spacing between neighbouring strokes. Returns the coefficient of variation and the mean.
std::pair<double, double> spacingVariation(const std::vector<ink::PenStroke>& strokes, uint32_t family,
                                           uint32_t maxLevel, double reach) {
    struct Seg {
        Vector3d a, b, n;
        size_t stroke;
    };
    std::vector<Seg> segs;
    std::map<std::array<int, 3>, std::vector<size_t>> grid;
    auto cell = [&](const Vector3d& p) {
        return std::array<int, 3>{int(std::floor(p.x() / reach)), int(std::floor(p.y() / reach)),
                                  int(std::floor(p.z() / reach))};
    };
    for (size_t k = 0; k < strokes.size(); ++k) {
        const ink::PenStroke& s = strokes[k];
        if (s.family != family || s.level > maxLevel) continue;
        for (size_t i = 0; i + 1 < s.points.size(); ++i) {
            Seg g{s.points[i].cast<double>(), s.points[i + 1].cast<double>(), s.normals[i].cast<double>(), k};
            grid[cell(0.5 * (g.a + g.b))].push_back(segs.size());
            segs.push_back(g);
        }
    }
    std::vector<double> distances;
    for (size_t k = 0; k < strokes.size(); ++k) {
        const ink::PenStroke& s = strokes[k];
        if (s.family != family || s.level > maxLevel) continue;
        for (size_t i = 0; i < s.points.size(); i += 3) {
            Vector3d p = s.points[i].cast<double>(), n = s.normals[i].cast<double>();
            auto c = cell(p);
            double best = reach;
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                        if (it == grid.end()) continue;
                        for (size_t j : it->second)
                            if (segs[j].stroke != k && segs[j].n.dot(n) > 0.5)
                                best = std::min(best, segmentDistance(p, segs[j].a, segs[j].b));
                    }
            if (best < reach) distances.push_back(best);
        }
    }
    double mean = 0, var = 0;
    for (double d : distances) mean += d;
    mean /= double(std::max<size_t>(1, distances.size()));
    for (double d : distances) var += (d - mean) * (d - mean);
    var /= double(std::max<size_t>(1, distances.size()));
    return {std::sqrt(var) / mean, mean};
}

}  // namespace

TEST_CASE(
    "hatching: the bunny's strokes at 1024² are long, evenly spaced, in no one direction, and clear of the halos" *
    doctest::test_suite("gpu")) {
    GpuFixture gpu;
    ink::LineOptions lines;
    lines.contours = lines.hatching = true;
    ink::Scene scene(gpu.ctx, ink::loadModel(INKWELL_SOURCE_DIR "/assets/bunny.obj", {684}), ink::DrawStyle::Stipple,
                     ink::RefineOptions{}, lines);
    REQUIRE(scene.hatching.size() > 100);
    const ink::Camera camera;
    scene.traceContours(camera);
    REQUIRE(!scene.contours.empty());

    // Spacing between neighbouring strokes of one family, on the surface: the coarse level alone (light tones) and
    // both levels (dark tones).
    const double d = lines.hatch.spacing;
    for (uint32_t family : {0u, 1u})
        for (uint32_t level : {0u, 1u}) {
            auto [cv, mean] = spacingVariation(scene.hatching, family, level, 4 * d);
            CAPTURE(family);
            CAPTURE(level);
            MESSAGE("family " << family << " levels ≤ " << level << ": mean spacing " << mean / d
                              << " × the finest, coefficient of variation " << cv);
            CHECK(cv <= 0.3);
            CHECK(mean == doctest::Approx(level == 0 ? 2 * d : d).epsilon(0.3));
        }

    // Both ways to the pixels: quads in a graphics pipeline (GPUs) and stamps in compute (what lavapipe is given).
    for (auto raster : {ink::RenderStyle::LineRaster::Quads, ink::RenderStyle::LineRaster::Stamps}) {
        const bool stamps = raster == ink::RenderStyle::LineRaster::Stamps;
        CAPTURE(stamps);
        ink::RenderStyle style;
        style.supersample = 1;
        style.drawDots = false;
        style.lineRaster = raster;
        ink::OffscreenRenderer renderer(gpu.ctx, 1024, 1024, style, scene.pointers(), scene.strokes.get());
        ink::RgbaImage image = renderer.render(camera);

        // Visible pieces: runs of consecutive drawn segments of one stroke.
        std::vector<uint32_t> strokeOf = ink::segmentStrokes(scene.hatching);
        std::vector<ink::DrawnSegment> drawn = renderer.drawnSegments(ink::StrokeBuffers::Hatching);
        REQUIRE(drawn.size() > 1000);
        std::sort(drawn.begin(), drawn.end(), [](auto& x, auto& y) { return x.segment < y.segment; });
        std::vector<double> pieces;
        for (size_t i = 0; i < drawn.size(); ++i) {
            double length = glm::length(drawn[i].b - drawn[i].a);
            if (i > 0 && drawn[i].segment == drawn[i - 1].segment + 1 &&
                strokeOf[drawn[i].segment] == strokeOf[drawn[i - 1].segment])
                pieces.back() += length;
            else
                pieces.push_back(length);
        }
        // Dashes: pieces under half the run a stroke needs (RenderStyle::hatchMinRun, 40 px here) can only be
        // cut by the image's edge or by the walk's reach (SEG_REACH segments); a hidden stroke showing through a
        // gap in the depth grid made them (here 8 of 174 pieces on lavapipe, none now).
        const size_t dashes = size_t(std::count_if(pieces.begin(), pieces.end(), [](double p) { return p < 20.0; }));
        std::nth_element(pieces.begin(), pieces.begin() + pieces.size() / 2, pieces.end());
        double median = pieces[pieces.size() / 2];
        // No screen direction carries most of the ink: the share of the drawn length within the two busiest ±10°
        // windows (about 0.23 for directions spread evenly, 1 for graph paper).
        std::vector<double> histogram(180, 0.0);
        double total = 0;
        for (const ink::DrawnSegment& s : drawn) {
            const glm::vec2 d = s.b - s.a;
            const double length = glm::length(d);
            if (!(length > 0)) continue;
            histogram[size_t(std::fmod(std::atan2(d.y, d.x) * 180 / M_PI + 360.0, 180.0)) % 180] += length;
            total += length;
        }
        auto window = [&](int c) {
            double sum = 0;
            for (int k = -10; k <= 10; ++k) sum += histogram[size_t((c + k + 180) % 180)];
            return sum;
        };
        int first = 0;
        for (int c = 1; c < 180; ++c)
            if (window(c) > window(first)) first = c;
        const double top = window(first);
        for (int k = -10; k <= 10; ++k) histogram[size_t((first + k + 180) % 180)] = 0;
        int second = 0;
        for (int c = 1; c < 180; ++c)
            if (window(c) > window(second)) second = c;
        const double share = (top + window(second)) / total;
        MESSAGE(drawn.size() << " hatching segments drawn in " << pieces.size() << " visible pieces, median " << median
                             << " px, " << dashes << " under 20 px; ink share of the two busiest directions " << share);
        CHECK(dashes <= pieces.size() / 100);
        CHECK(median >= 40.0);  // RenderStyle::hatchMinRun: 4% of 1024 (of visible run), unless cut by the image
        // The layout follows the sample set: over refinement seeds 1–6 the share was 0.43–0.53 (0.51 at seed 1),
        // and with the seeds spread over each side of a thin wall on its own (clean.h) 0.41–0.58 (0.58 at seed 1),
        // the same spread: no one direction either way, where graph paper reads 1.
        CHECK(share <= 0.62);

        // The halo: around every visible interior contour, the band between its ink and the halo's edge is paper
        // unless another contour inks it. Without the halo, hatching inks part of that band (the test can fail).
        std::vector<ink::DrawnSegment> contours = renderer.drawnSegments(ink::StrokeBuffers::Contours);
        const float pen = 0.5f * style.penWidth, halo = pen + style.haloWidth;
        auto distance = [](glm::vec2 p, const ink::DrawnSegment& s) {
            glm::vec2 d = s.b - s.a;
            float t = std::clamp(glm::dot(p - s.a, d) / std::max(glm::dot(d, d), 1e-12f), 0.0f, 1.0f);
            return glm::length(p - (s.a + t * d));
        };
        std::vector<uint8_t> band(1024 * 1024, 0);  // 1: in a halo band, 2: on some contour's ink
        size_t interior = 0;
        for (const ink::DrawnSegment& s : contours) {
            if (!(s.flags & ink::kSegmentVisible)) continue;
            bool isInterior = (s.flags & ink::kSegmentInterior) != 0;
            interior += isInterior;
            glm::vec2 lo = glm::min(s.a, s.b) - halo - 1.0f, hi = glm::max(s.a, s.b) + halo + 1.0f;
            for (int y = std::max(0, int(lo.y)); y <= std::min(1023, int(hi.y)); ++y)
                for (int x = std::max(0, int(lo.x)); x <= std::min(1023, int(hi.x)); ++x) {
                    float dist = distance(glm::vec2(x + 0.5f, y + 0.5f), s);
                    uint8_t& b = band[size_t(y) * 1024 + size_t(x)];
                    if (dist < pen + 1.5f)
                        b = 2;
                    else if (isInterior && dist < halo - 0.75f && b == 0)
                        b = 1;
                }
        }
        REQUIRE(interior > 20);
        auto inkedInBand = [&](const ink::RgbaImage& img) {
            size_t inked = 0, pixels = 0;
            for (size_t i = 0; i < band.size(); ++i)
                if (band[i] == 1) {
                    ++pixels;
                    inked += img.pixels[4 * i] < 250;
                }
            return std::pair{inked, pixels};
        };
        auto [inked, bandPixels] = inkedInBand(image);
        MESSAGE(interior << " interior contour segments, " << bandPixels << " halo pixels, " << inked << " inked");
        CHECK(bandPixels > 300);
        CHECK(inked == 0);
        style.haloWidth = 0;
        renderer.setStyle(style);
        // The control: without the halo the hatching does cross the band, an 80th of it at least (on lavapipe 43
        // of its 887 pixels; with the seeds of each side of a thin wall spread on their own, clean.h, 29 and 15
        // of 889 as quads and stamps: where the strokes lie follows the sample set).
        auto [inkedWithout, unused] = inkedInBand(renderer.render(camera));
        MESSAGE(inkedWithout << " of them inked without the halo");
        CHECK(inkedWithout * 80 > bandPixels);
    }
    gpu.requireNoValidationErrors();
}

// The torus's contour traced nearly edge-on (azimuth 80°, 20° up): much of the inner contour is behind the tube.
struct EdgeOnTorus {
    static ink::LineOptions contours() {
        ink::LineOptions lines;
        lines.contours = true;
        return lines;
    }
    static ink::RefineOptions levels3() {
        ink::RefineOptions options;
        options.levels = 3;
        return options;
    }
    ink::Camera camera;
    ink::Scene scene;
    explicit EdgeOnTorus(GpuFixture& gpu) : scene(gpu.ctx, torus(), ink::DrawStyle::Stipple, levels3(), contours()) {
        camera.azimuthDeg = 80.0f;
        camera.elevationDeg = 20.0f;
        scene.traceContours(camera);
    }
};

TEST_CASE("contours: each frame decides on the device which contour segments are hidden, as ray casting does" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    EdgeOnTorus t(gpu);
    ink::Scene& scene = t.scene;
    const ink::Camera& camera = t.camera;
    const ink::Model& m = scene.model;
    const double scale = m.surface.frame.scale;
    const Vector3d centre = m.surface.frame.toNormalized(Vector3d::Zero());
    ink::RenderStyle style;
    style.supersample = 1;
    style.hiddenLines = true;
    ink::OffscreenRenderer renderer(gpu.ctx, 512, 512, style, scene.pointers(), scene.strokes.get());
    renderer.render(camera);
    std::vector<ink::DrawnSegment> drawn = renderer.drawnSegments(ink::StrokeBuffers::Contours);
    std::vector<Eigen::Vector3f> mids;
    for (const ink::PenStroke& s : scene.contours)
        for (size_t i = 0; i + 1 < s.points.size() + (s.closed ? 1 : 0); ++i)
            mids.push_back(0.5f * (s.points[i] + s.points[(i + 1) % s.points.size()]));
    REQUIRE(drawn.size() == mids.size());  // with hidden lines, every segment is drawn one way or the other
    // The analytic torus's distance, marched from the eye towards each segment's midpoint.
    glm::vec3 e = camera.eye();
    const Vector3d eye(e.x, e.y, e.z);
    auto sdf = [&](const Vector3d& x) {
        Vector3d p = (x - centre) / scale;
        return scale * (std::hypot(std::hypot(p.x(), p.y()) - kR, p.z()) - kr);
    };
    std::vector<bool> occluded(drawn.size(), false);
    for (size_t k = 0; k < drawn.size(); ++k) {
        Vector3d target = mids[drawn[k].segment].cast<double>(), dir = (target - eye).normalized();
        for (double t = 0, end = (target - eye).norm() - 0.01; t < end;) {
            double dist = sdf(eye + t * dir);
            if (dist < 1e-5) {
                occluded[k] = true;
                break;
            }
            t += dist;
        }
    }
    // Where the contour passes behind the surface (at a cusp or behind another contour) the depth grid's cells
    // blur the change over a few pixels: a disagreement within 6 pixels of a segment that ray casting decides the
    // other way is excused.
    size_t agree = 0, hidden = 0, unexcused = 0;
    auto mid = [&](size_t k) { return 0.5f * (drawn[k].a + drawn[k].b); };
    for (size_t k = 0; k < drawn.size(); ++k) {
        bool deviceHidden = (drawn[k].flags & ink::kSegmentHidden) != 0;
        hidden += deviceHidden;
        agree += deviceHidden == occluded[k];
        if (deviceHidden == occluded[k]) continue;
        bool excused = false;
        for (size_t j = 0; j < drawn.size() && !excused; ++j)
            excused = occluded[j] != occluded[k] && glm::length(mid(j) - mid(k)) < 6.0f;
        unexcused += !excused;
    }
    MESSAGE(drawn.size() << " contour segments, " << hidden << " hidden, " << agree << " agree with ray casting, "
                         << unexcused << " disagree farther than 6 px from a change of visibility");
    CHECK(hidden > drawn.size() / 10);
    // 600 of 615 on lavapipe by the depth test alone; 614 with the pieces the torus's inner wall hides marked so
    // (ink::markOccluded: concave along the view). A GPU traces on the device (autoOnDevice): a little room.
    CHECK(double(agree) >= 0.98 * double(drawn.size()));
    CHECK(unexcused <= drawn.size() / 100);
    gpu.requireNoValidationErrors();
}

// The visibility of a contour along its stroke (lines_runs.comp): where a stroke passes behind the surface it
// changes once, not in dashes. Without the median (lineMinRun 0) the depth grid's cells flip short runs.
TEST_CASE("contours: visibility changes along a stroke without dashes" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    EdgeOnTorus t(gpu);
    ink::Scene& scene = t.scene;
    const ink::Camera& camera = t.camera;
    // The depth test's dashes, which the pieces the surface hides (ink::markOccluded) no longer show here: unmarked,
    // as a surface whose hidden stretch is convex would give them.
    REQUIRE(std::any_of(scene.contours.begin(), scene.contours.end(), [](auto& c) { return c.occluded; }));
    for (ink::PenStroke& c : scene.contours) c.occluded = false;
    scene.strokes->set(ink::StrokeBuffers::Contours, scene.contours);
    const std::vector<uint32_t> strokeOf = ink::segmentStrokes(scene.contours);
    // Runs of one visibility between runs of the other, shorter than `window` pixels, and the number of runs.
    auto dashes = [&](float minRun, size_t& runs) {
        ink::RenderStyle style;
        style.supersample = 1;
        style.hiddenLines = true;
        style.lineMinRun = minRun;
        ink::OffscreenRenderer renderer(gpu.ctx, 512, 512, style, scene.pointers(), scene.strokes.get());
        renderer.render(camera);
        std::vector<ink::DrawnSegment> drawn = renderer.drawnSegments(ink::StrokeBuffers::Contours);
        std::sort(drawn.begin(), drawn.end(), [](auto& a, auto& b) { return a.segment < b.segment; });
        struct Run {
            uint32_t stroke;
            bool visible;
            float length;
        };
        std::vector<Run> all;
        for (size_t i = 0; i < drawn.size(); ++i) {
            const bool visible = (drawn[i].flags & ink::kSegmentVisible) != 0;
            const float length = glm::length(drawn[i].b - drawn[i].a);
            const bool joins = i > 0 && drawn[i].segment == drawn[i - 1].segment + 1 &&
                               strokeOf[drawn[i].segment] == strokeOf[drawn[i - 1].segment];
            if (joins && all.back().visible == visible)
                all.back().length += length;
            else
                all.push_back({strokeOf[drawn[i].segment], visible, length});
        }
        runs = all.size();
        size_t count = 0;
        const float window = 0.015f * 512;
        for (size_t k = 1; k + 1 < all.size(); ++k)
            count += all[k].length < window && all[k - 1].stroke == all[k].stroke && all[k + 1].stroke == all[k].stroke;
        return count;
    };
    size_t rawRuns = 0, runs = 0;
    const size_t raw = dashes(0.0f, rawRuns), kept = dashes(0.015f, runs);
    MESSAGE("runs of one visibility: " << rawRuns << " with " << raw << " dashes without the median, " << runs
                                       << " with " << kept << " with it");
    CHECK(kept == 0);
    CHECK(runs >= 4);  // the inner contour still passes behind the tube: the change itself stays
    gpu.requireNoValidationErrors();
    if (raw == 0) {
        // Lavapipe's depth grid gives the raw case 2 dashes in 9 runs; an NVIDIA H200's, since the splat disks
        // take the cells they cross, none: nothing there for the median to clean.
        skipTest(std::string("the depth grid gives ") + gpu.ctx.properties.deviceName +
                 " no dashes for the median to clean (" + std::to_string(rawRuns) + " runs)");
        return;
    }
    CHECK(runs < rawRuns);
}

// Hidden contours are one grey, however many of a stroke's segments cover a pixel (their round ends overlap at
// every joint, a wide pen's over several segments): with quads (a GPU's raster, blended by MIN) as with stamps.
// Over alpha blending each overlap darkened the grey again, to black on an H200 (`cli: the hidden lines' ...`).
TEST_CASE("contours: a wide hidden pen inks one grey, with quads as with stamps" * doctest::test_suite("gpu")) {
    GpuFixture gpu;
    EdgeOnTorus t(gpu);
    ink::Scene& scene = t.scene;
    const ink::Camera& camera = t.camera;
    for (auto raster : {ink::RenderStyle::LineRaster::Quads, ink::RenderStyle::LineRaster::Stamps}) {
        CAPTURE(raster == ink::RenderStyle::LineRaster::Stamps);
        ink::RenderStyle style;
        style.supersample = 1;
        style.drawDots = false;
        style.lineRaster = raster;
        ink::RgbaImage visible =
            ink::OffscreenRenderer(gpu.ctx, 512, 512, style, scene.pointers(), scene.strokes.get()).render(camera);
        style.hiddenLines = true;
        style.hiddenPenWidth = 4.0f;
        ink::RgbaImage both =
            ink::OffscreenRenderer(gpu.ctx, 512, 512, style, scene.pointers(), scene.strokes.get()).render(camera);
        // The pixels the hidden lines alone ink: 255 − 0.45 · 255 = 140 where wholly covered, lighter at the edges.
        size_t added = 0, full = 0;
        int darkest = 255;
        for (size_t i = 0; i < both.pixels.size(); i += 4)
            if (visible.pixels[i] == 255 && both.pixels[i] < 255) {
                ++added;
                full += both.pixels[i] <= 141;
                darkest = std::min(darkest, int(both.pixels[i]));
            }
        CAPTURE(added);
        CAPTURE(full);
        CHECK(added > 500);
        CHECK(darkest >= 139);
        CHECK(full > added / 4);  // a 4 px pen covers most of its pixels wholly
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("lines: render -o out.svg writes the pen lines as polylines in their own layers" *
          doctest::test_suite("cli")) {
    TempDir dir;
    const std::string svg = dir / "pen.svg";
    Run r = runInkwell("render " INKWELL_SOURCE_DIR
                       "/assets/bunny.obj --control-points 150 --levels 3 "
                       "--style contours+hatching --creases off --hidden-lines --size 256 256 -o " +
                       svg);
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    // One pen a layer, bottom first: the hidden contours, the hatching, the contours.
    for (const char* label :
         {"inkscape:label=\"1 hidden contour\"", "inkscape:label=\"2 hatching\"", "inkscape:label=\"3 contour\""}) {
        CAPTURE(label);
        CHECK(s.find(label) != std::string::npos);
    }
    CHECK(s.find("inkscape:label=\"4") == std::string::npos);
    CHECK(s.find("<circle") == std::string::npos);  // no dots without a dot style
}

// ---- The contour traced on the device (contour_device.h) ------------------------------------------------------

namespace {

// Marches for chainMarches: each from node `from`'s forward or backward port to a port of `to`, its vertices the
// node's position then `extra` points along the way (points appended to `points`).
struct MarchBuilder {
    std::vector<ink::ContourNodeInfo> nodes;
    std::vector<Vector3d> points, normals;
    std::vector<ink::ContourMarch> marches;
    uint32_t node(const Vector3d& p, const Vector3d& t) {
        nodes.push_back({p, Vector3d::UnitZ(), t.normalized()});
        return uint32_t(nodes.size() - 1);
    }
    void march(uint32_t from, bool fromForward, uint32_t to, bool toForward, int extra) {
        ink::ContourMarch m;
        m.from = from;
        m.fromForward = fromForward;
        m.to = to;
        m.toForward = toForward;
        m.first = uint32_t(points.size());
        const Vector3d a = nodes[from].position, b = to == ink::ContourMarch::kNoNode ? a : nodes[to].position;
        for (int k = 0; k <= extra; ++k) {
            points.push_back(a + (b - a) * (double(k) / (extra + 1)));
            normals.push_back(Vector3d::UnitZ());
        }
        m.count = uint32_t(extra + 1);
        m.backward = !fromForward;  // as the device marks a seed's backward march
        marches.push_back(m);
    }
};

}  // namespace

TEST_CASE("contours: the device's marches chain into curves through flipped tangents, each stretch once" *
          doctest::test_suite("unit")) {
    // A square of four nodes, A → B → C → D → A, but C's tangent points back (its orientation flipped): B's march
    // arrives at C's forward port, C marches back to B (the same stretch again), and D, running against C, reaches
    // C's backward port.
    MarchBuilder b;
    const uint32_t A = b.node({0, 0, 0}, {1, 0, 0}), B = b.node({1, 0, 0}, {0, 1, 0}), C = b.node({1, 1, 0}, {1, 0, 0}),
                   D = b.node({0, 1, 0}, {0, -1, 0});
    b.march(A, true, B, false, 3);
    b.march(B, true, C, true, 3);  // against C's tangent: its forward port
    b.march(C, true, B, true, 3);  // C's own forward march: back over B's (the same ports)
    b.march(D, true, A, false, 3);
    b.march(C, false, D, false, 3);  // C's backward march reaches D from behind
    std::vector<ink::ChainedCurve> curves = ink::chainMarches(b.marches, b.nodes, b.points, b.normals, 1e-4);
    REQUIRE(curves.size() == 1);
    CHECK(curves[0].closed);
    CHECK(curves[0].points.size() == 16);  // four stretches of four points each, none twice
    std::set<std::tuple<double, double>> seen;
    for (const Vector3d& p : curves[0].points) seen.insert({p.x(), p.y()});
    CHECK(seen.size() == 16);

    // A march that passed a node without meeting it (A's, to C past B) loses its ports to the shorter ones; a
    // march ending in the open is an end; nodes at one place are one.
    MarchBuilder o;
    const uint32_t P = o.node({0, 0, 0}, {1, 0, 0}), Q = o.node({1, 0, 0}, {1, 0, 0}), R = o.node({2, 0, 0}, {1, 0, 0}),
                   R2 = o.node({2, 0, 1e-6}, {-1, 0, 0});
    o.march(P, true, R, false, 7);  // passed Q
    o.march(P, true, Q, false, 3);
    o.march(Q, true, R2, true, 3);                           // meets R's twin, running against it: R's backward port
    o.march(R, true, ink::ContourMarch::kNoNode, false, 5);  // ends in the open
    curves = ink::chainMarches(o.marches, o.nodes, o.points, o.normals, 1e-4);
    REQUIRE(curves.size() == 1);
    CHECK(!curves[0].closed);
    CHECK(curves[0].points.size() == 4 + 4 + 6);  // from P's free backward port: P's march, Q's, R's open tail
    CHECK((curves[0].points.front() - o.nodes[P].position).norm() < 1e-12);

    // Seeds S and T march both ways at once. S's forward march stopped at U and went on from there to T; T's
    // backward march reached S sooner, but the forward ones take their ports first: one curve S → U → T, not T's
    // march with U's left over as a piece of its own.
    MarchBuilder w;
    const uint32_t S = w.node({0, 0, 0}, {1, 0, 0}), T = w.node({3, 0, 0}, {1, 0, 0}), U = w.node({2, 0, 0}, {1, 0, 0});
    w.march(S, true, U, false, 9);  // too long: U goes on
    w.march(U, true, T, false, 7);
    w.march(T, false, S, true, 5);  // backward, shorter than S's and U's each
    curves = ink::chainMarches(w.marches, w.nodes, w.points, w.normals, 1e-4);
    REQUIRE(curves.size() == 1);
    CHECK(!curves[0].closed);
    CHECK(curves[0].points.size() == 10 + 8 + 1);  // S's march, U's, T at the end
    w.marches.back().backward = false;             // shortest first alone: T's march, and U's pieces apart
    CHECK(ink::chainMarches(w.marches, w.nodes, w.points, w.normals, 1e-4).size() > 1);

    // The rest of a march that lost its ports goes with it. E's forward march stopped at G and went on to F; Z,
    // whose tangent runs the other way, reached E's front sooner over the same stretch and took E's forward port.
    // G's march is then a second copy of part of Z's: no curve passes through G.
    MarchBuilder v;
    const uint32_t E = v.node({0, 0, 0}, {1, 0, 0}), F = v.node({3, 0, 0}, {1, 0, 0}), G = v.node({2, 0, 0}, {1, 0, 0}),
                   Z = v.node({2.5, 0, 0}, {-1, 0, 0});
    v.nodes[G].continuation = true;
    v.march(E, true, G, false, 9);  // too long: G goes on
    v.march(G, true, F, false, 3);
    v.march(Z, true, E, true, 3);  // against E's tangent: its forward port
    auto throughG = [&](const std::vector<ink::ChainedCurve>& list) {
        size_t through = 0;
        for (const ink::ChainedCurve& c : list)  // (a curve of one node alone is no stroke: DeviceContours drops it)
            for (const Vector3d& p : c.points)
                through += c.points.size() > 1 && (p - v.nodes[G].position).norm() < 1e-9;
        return through;
    };
    CHECK(throughG(ink::chainMarches(v.marches, v.nodes, v.points, v.normals, 1e-4)) == 0);
    v.nodes[G].continuation = false;  // kept as a march of its own, it draws the stretch again
    CHECK(throughG(ink::chainMarches(v.marches, v.nodes, v.points, v.normals, 1e-4)) > 0);
}

TEST_CASE("contours: traced on the device, the torus's contour lies on both equations and on the CPU's curve" *
          doctest::test_suite("gpu")) {
    GpuFixture gpu;
    const ink::Model& m = torus();
    ink::RefineOptions options;
    options.levels = 3;
    Refinement refined(gpu.ctx, m.surface, options);
    REQUIRE(ink::DeviceContours::supports(refined.r));
    const std::vector<ink::PointRecord> drawn = ink::readDrawnPoints(gpu.ctx, refined.r);
    std::vector<ink::SurfaceSample> samples;
    for (const ink::PointRecord& p : drawn)
        samples.push_back(
            {Vector3d(p.position[0], p.position[1], p.position[2]), Vector3d(p.normal[0], p.normal[1], p.normal[2])});
    ink::DeviceContours tracer(gpu.ctx, refined.r, uint32_t(drawn.size()), {});
    for (float elevation : {15.0f, 50.0f}) {
        CAPTURE(elevation);
        ink::Camera camera;
        camera.azimuthDeg = 30.0f;
        camera.elevationDeg = elevation;
        const glm::vec3 e = camera.eye();
        const Vector3d eye(e.x, e.y, e.z);
        ink::ContourStats stats, cpuStats;
        const std::vector<ink::PenStroke> pieces = tracer.trace(m.surface, eye, &stats);
        const std::vector<ink::PenStroke> cpu = ink::traceContours(m.surface, eye, samples, {}, &cpuStats);
        CHECK(stats.onDevice);
        CHECK(stats.deviceMs > 0.0);
        CHECK(stats.evaluations > 0);
        // A torus seen from outside its hole's axis: at most two closed contour curves, as the CPU finds.
        CHECK(stats.curves == cpuStats.curves);
        CHECK(stats.closedCurves == stats.curves);
        REQUIRE(!pieces.empty());
        // Every vertex is on both equations (float: within 1e-5 of the diagonal, and the view ray within 0.1° of
        // the tangent plane), and each curve lies within a pixel (0.001) of the other's: every vertex of one near a
        // point of the other's polylines (sampled every 0.0002).
        auto sampled = [](const std::vector<ink::PenStroke>& strokes) {
            ink::PointHash h(0.002);
            for (const ink::PenStroke& s : strokes)
                for (size_t i = 0; i + 1 < s.points.size() + (s.closed ? 1 : 0); ++i) {
                    const Vector3d a = s.points[i].cast<double>(),
                                   b = s.points[(i + 1) % s.points.size()].cast<double>();
                    const int n = 1 + int((b - a).norm() / 0.0002);
                    for (int k = 0; k <= n; ++k)
                        h.add(a + (b - a) * (double(k) / n), s.normals[i].cast<double>(), 0, 0);
                }
            return h;
        };
        const ink::PointHash cpuCurve = sampled(cpu), deviceCurve = sampled(pieces);
        size_t farFromCpu = 0, farFromDevice = 0, devicePoints = 0;
        for (const ink::PenStroke& s : pieces)
            for (size_t i = 0; i < s.points.size(); ++i) {
                Vector3d x = s.points[i].cast<double>(), g;
                double f = m.surface.eval(x, g);
                CHECK(std::abs(f) / g.norm() < 1e-5);
                CHECK(std::abs(g.normalized().dot((x - eye).normalized())) < 2e-3);
                farFromCpu += !cpuCurve.near(x, s.normals[i].cast<double>(), 0.001);
                ++devicePoints;
            }
        for (const ink::PenStroke& s : cpu)
            for (size_t i = 0; i < s.points.size(); ++i)
                farFromDevice += !deviceCurve.near(s.points[i].cast<double>(), s.normals[i].cast<double>(), 0.001);
        CAPTURE(devicePoints);
        CHECK(farFromCpu == 0);
        CHECK(farFromDevice == 0);
        // The same pieces again: nothing depends on the order the device's invocations ran in.
        const std::vector<ink::PenStroke> again = tracer.trace(m.surface, eye);
        REQUIRE(again.size() == pieces.size());
        for (size_t k = 0; k < pieces.size(); ++k) CHECK(again[k].points == pieces[k].points);
    }
    gpu.requireNoValidationErrors();
}

TEST_CASE("lines: --contour-tracer device draws the contour the CPU draws, and says where it was traced" *
          doctest::test_suite("cli")) {
    TempDir dir;
    auto render = [&](const std::string& name, const std::string& extra) {
        Run r = runInkwell("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --style contours --size 256 256 -o " +
                           (dir / (name + ".png")) + " --stats " + (dir / (name + ".json")) + " " + extra);
        INFO(r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(dir / (name + ".json"));
        std::stringstream text;
        text << in.rdbuf();
        return text.str();
    };
    const std::string device = render("device", "--contour-tracer device"), cpu = render("cpu", "--contour-tracer cpu");
    CHECK(device.find("\"traced_on\": \"device\"") != std::string::npos);
    CHECK(cpu.find("\"traced_on\": \"cpu\"") != std::string::npos);
    const ink::RgbaImage a = ink::readPng(dir / "device.png"), b = ink::readPng(dir / "cpu.png");
    REQUIRE(a.width == b.width);
    size_t inkA = 0, inkB = 0, differ = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4) {
        inkA += a.pixels[i] < 128;
        inkB += b.pixels[i] < 128;
        differ += (a.pixels[i] < 128) != (b.pixels[i] < 128);
    }
    CAPTURE(inkA);
    CAPTURE(inkB);
    CAPTURE(differ);
    CHECK(inkA > 300);
    CHECK(std::abs(double(inkA) - double(inkB)) < 0.15 * double(inkB));
    // A global fit is traced on the CPU, and says so.
    Run global = runInkwell("render " INKWELL_SOURCE_DIR
                            "/assets/bunny.obj --fit global --control-points 300 "
                            "--style contours --size 128 128 --contour-tracer device -o " +
                            (dir / "g.png"));
    INFO(global.output);
    CHECK(global.status == 0);
    CHECK(global.output.find("the contour is traced on the CPU") != std::string::npos);
    Run bad = runInkwell("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --contour-tracer gpu -o " + (dir / "x.png"));
    CHECK(bad.status != 0);
    CHECK(bad.output.find("--contour-tracer") != std::string::npos);
}

TEST_CASE("lines: --hatch-field device solves the cross field on the device and hatches as the CPU does" *
          doctest::test_suite("cli")) {
    TempDir dir;
    auto render = [&](const std::string& name, const std::string& extra) {
        Run r = runInkwell("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --style hatching --size 256 256 -o " +
                           (dir / (name + ".png")) + " --stats " + (dir / (name + ".json")) + " " + extra);
        INFO(r.output);
        REQUIRE(r.status == 0);
        std::ifstream in(dir / (name + ".json"));
        const nlohmann::json stats = nlohmann::json::parse(in);
        return std::pair(stats.at("lines").at("hatching"), r.output);
    };
    const auto [device, deviceOutput] = render("device", "--hatch-field device");
    const auto [cpu, cpuOutput] = render("cpu", "--hatch-field cpu");
    CHECK(device.at("field_on") == "device");
    CHECK(cpu.at("field_on") == "cpu");
    CHECK(device.at("field_device_ms").get<double>() > 0);
    CHECK(cpu.at("field_device_ms").get<double>() == 0);
    // The same strokes up to float (the field agrees to about 1e-5 degrees on the torus, test_hatching.cpp).
    const double strokes = cpu.at("strokes").get<double>(), length = cpu.at("length").get<double>();
    REQUIRE(strokes > 100);
    CHECK(std::abs(device.at("strokes").get<double>() - strokes) <= 0.03 * strokes);
    CHECK(std::abs(device.at("length").get<double>() - length) <= 0.03 * length);
    // A global fit is solved on the CPU, and says so.
    Run global = runInkwell("render " INKWELL_SOURCE_DIR
                            "/assets/bunny.obj --fit global --control-points 300 --style hatching --size 128 128 "
                            "--hatch-field device -o " +
                            (dir / "g.png"));
    INFO(global.output);
    CHECK(global.status == 0);
    CHECK(global.output.find("the hatching's cross field is solved on the CPU") != std::string::npos);
    Run bad = runInkwell("render " INKWELL_SOURCE_DIR "/assets/bunny.obj --hatch-field gpu -o " + (dir / "x.png"));
    CHECK(bad.status != 0);
    CHECK(bad.output.find("--hatch-field") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "x.png"));
}
