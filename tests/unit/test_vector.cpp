// Vector output (engine/vector/vector.h, path_order.h; `render -o out.svg|pdf`): the layout and order of pen paths,
// and the SVG and PDF of a real frame drawn by independent renderers (rsvg-convert, pdftoppm) against its PNG.
// GCC 12 with the sanitizers warns inside libstdc++'s <regex> (a std::function "may be used uninitialized" in
// _Compiler), which -Werror turns into an error; the warning is in the library, not here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "base/common.h"
#include "base/image.h"
#include "run_command.h"
#include "skip.h"
#include "temp_dir.h"
#include "vector/path_order.h"
#include "vector/vector.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A 3×3 box blur of the image's luma.
std::vector<float> blurredLuma(const ink::RgbaImage& image) {
    const int w = int(image.width), h = int(image.height);
    std::vector<float> luma(size_t(w) * size_t(h)), out(luma.size());
    for (size_t i = 0; i < luma.size(); ++i) {
        const uint8_t* p = &image.pixels[4 * i];
        // Over white: rsvg-convert and pdftoppm leave the page transparent where nothing is drawn.
        float a = float(p[3]) / 255.0f;
        luma[i] = (0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2]) * a + 255.0f * (1.0f - a);
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float sum = 0;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= w || v >= h) continue;
                    sum += luma[size_t(v) * size_t(w) + size_t(u)];
                    ++count;
                }
            out[size_t(y) * size_t(w) + size_t(x)] = sum / float(count);
        }
    return out;
}

struct Difference {
    double fraction;    // of pixels differing by more than 64 after the blur
    size_t inkA, inkB;  // pixels darker than 128 before
};

Difference compareBlurred(const ink::RgbaImage& a, const ink::RgbaImage& b, int shift = 0) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    std::vector<float> la = blurredLuma(a), lb = blurredLuma(b);
    size_t differ = 0;
    // `shift`: b moved right by that many pixels (a control: a misplaced drawing must fail the comparison).
    const size_t w = a.width;
    for (size_t i = 0; i < la.size(); ++i) {
        size_t x = i % w;
        float vb = x >= size_t(shift) ? lb[i - size_t(shift)] : 255.0f;
        differ += std::abs(la[i] - vb) > 64.0f;
    }
    auto ink = [](const ink::RgbaImage& im) {
        size_t n = 0;
        for (size_t i = 0; i < im.pixels.size(); i += 4) n += im.pixels[i + 3] > 128 && im.pixels[i] < 128;
        return n;
    };
    return {double(differ) / double(la.size()), ink(a), ink(b)};
}

// The SVG as a plotter program reads it: its size, layers and paths.
struct ParsedSvg {
    std::string width, height, viewBox;
    struct Layer {
        std::string groupmode, label, fill, strokeWidth;
        std::vector<std::string> paths;
    };
    std::vector<Layer> layers;
    size_t elements = 0;  // every element other than svg, g and path
};

std::string attribute(const std::string& tag, const std::string& name) {
    std::smatch m;
    std::regex re("\\s" + name + "=\"([^\"]*)\"");
    return std::regex_search(tag, m, re) ? m[1].str() : std::string("<missing>");
}

ParsedSvg parseSvg(const std::string& text) {
    ParsedSvg svg;
    size_t at = 0;
    while ((at = text.find('<', at)) != std::string::npos) {
        size_t end = text.find('>', at);
        REQUIRE(end != std::string::npos);
        std::string tag = text.substr(at, end - at + 1);
        at = end + 1;
        if (tag.rfind("<?xml", 0) == 0 || tag.rfind("</", 0) == 0) continue;
        if (tag.rfind("<svg", 0) == 0) {
            svg.width = attribute(tag, "width");
            svg.height = attribute(tag, "height");
            svg.viewBox = attribute(tag, "viewBox");
        } else if (tag.rfind("<g", 0) == 0) {
            svg.layers.push_back({attribute(tag, "inkscape:groupmode"),
                                  attribute(tag, "inkscape:label"),
                                  attribute(tag, "fill"),
                                  attribute(tag, "stroke-width"),
                                  {}});
        } else if (tag.rfind("<path", 0) == 0) {
            REQUIRE(!svg.layers.empty());
            svg.layers.back().paths.push_back(attribute(tag, "d"));
        } else {
            ++svg.elements;
        }
    }
    return svg;
}

// A path's length and its extent, from the commands the writer uses (M, L with absolute points; a with a
// relative end point; z, which it does not write).
struct PathShape {
    double length = 0;
    double minX = 1e30, minY = 1e30, maxX = -1e30, maxY = -1e30;
    double startX = 0, startY = 0, endX = 0, endY = 0;  // where the pen goes down and up
};

PathShape shapeOf(const std::string& d) {
    PathShape s;
    std::istringstream in(d);
    char command = 0;
    double x = 0, y = 0, x0 = 0, y0 = 0;
    auto extend = [&](double px, double py, double r) {
        s.minX = std::min(s.minX, px - r), s.maxX = std::max(s.maxX, px + r);
        s.minY = std::min(s.minY, py - r), s.maxY = std::max(s.maxY, py + r);
    };
    while (in >> std::ws && !in.eof()) {
        int c = in.peek();
        if (std::isalpha(c)) {
            command = char(in.get());
            if (command == 'z') {
                s.length += std::hypot(x - x0, y - y0);
                x = x0, y = y0;
                continue;
            }
        }
        if (command == 'M') {
            in >> x >> y;
            x0 = x, y0 = y;
            extend(x, y, 0);
            command = 'L';
        } else if (command == 'L') {
            double nx, ny;
            in >> nx >> ny;
            s.length += std::hypot(nx - x, ny - y);
            x = nx, y = ny;
            extend(x, y, 0);
        } else if (command == 'H') {  // a filled dot's step along the radius
            double nx;
            in >> nx;
            s.length += std::abs(nx - x);
            x = nx;
            extend(x, y, 0);
        } else if (command == 'a') {
            double rx, ry, rotation, large, sweep, dx, dy;
            in >> rx >> ry >> rotation >> large >> sweep >> dx >> dy;
            REQUIRE(rx == ry);
            // A half circle from (x, y) to (x + dx, y): its centre half way, its length π r.
            extend(x + dx / 2, y + dy / 2, rx);
            s.length += M_PI * rx;
            x += dx, y += dy;
        } else {
            FAIL("unexpected path data: " << d);
        }
        REQUIRE_FALSE(in.fail());
    }
    s.startX = x0, s.startY = y0, s.endX = x, s.endY = y;
    return s;
}

const std::string kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";

}  // namespace

TEST_CASE("vector: ordering keeps every path, reverses polylines only whole, and cuts random travel by far" *
          doctest::test_suite("unit")) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 200);
    std::vector<ink::PlotPath> paths;
    for (int i = 0; i < 20000; ++i) {
        ink::PlotPath p;
        glm::dvec2 c(u(rng), u(rng));
        if (i % 4 == 0) {
            p.points = {c, c + glm::dvec2(1, 0.5), c + glm::dvec2(2, 0)};
        } else {
            p.points = {c};
            p.radius = 0.2;
        }
        paths.push_back(p);
    }
    const glm::dvec2 home(0, 0);
    std::vector<ink::PlotPath> ordered = paths;
    ink::orderPaths(ordered, home);
    REQUIRE(ordered.size() == paths.size());
    double before = ink::travel(paths, home), after = ink::travel(ordered, home);
    MESSAGE("travel " << before << " mm -> " << after << " mm");
    CHECK(after < before / 20);
    // The same paths: each polyline as given or reversed, each circle as given.
    auto key = [](const ink::PlotPath& p) {
        std::vector<double> k{p.radius};
        std::vector<glm::dvec2> pts = p.points;
        if (!p.circle() && std::lexicographical_compare(
                               pts.rbegin(), pts.rend(), pts.begin(), pts.end(),
                               [](glm::dvec2 a, glm::dvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }))
            std::reverse(pts.begin(), pts.end());
        for (glm::dvec2 p : pts) k.push_back(p.x), k.push_back(p.y);
        return k;
    };
    std::vector<std::vector<double>> a, b;
    for (const auto& p : paths) a.push_back(key(p));
    for (const auto& p : ordered) b.push_back(key(p));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    CHECK(a == b);
    // Deterministic: the same input, the same order.
    std::vector<ink::PlotPath> again = paths;
    ink::orderPaths(again, home);
    bool same = true;
    for (size_t i = 0; i < again.size(); ++i) same = same && again[i].points == ordered[i].points;
    CHECK(same);
}

TEST_CASE("vector: 2-opt undoes a crossing greedy leaves, and touching strokes merge into one path" *
          doctest::test_suite("unit")) {
    // Four short strokes on a line, given out of order: ordered, they are drawn end to end, and the strokes that
    // touch (the ends coincide) become one path.
    auto line = [](double x0, double x1) {
        ink::PlotPath p;
        p.points = {{x0, 10}, {x1, 10}};
        return p;
    };
    std::vector<ink::PlotPath> paths{line(30, 20), line(0, 10), line(20, 10), line(40, 50)};
    ink::orderPaths(paths, {0, 10});
    CHECK(ink::travel(paths, {0, 10}) == doctest::Approx(10.0));  // only the gap from 30 to 40
    ink::mergeTouching(paths, 1e-3);
    REQUIRE(paths.size() == 2);
    CHECK(paths[0].points.size() == 4);
    CHECK(paths[0].points.front() == glm::dvec2(0, 10));
    CHECK(paths[0].points.back() == glm::dvec2(30, 10));
    CHECK(paths[0].length() == doctest::Approx(30.0));
}

TEST_CASE("vector: pen lines are simplified, their retraced stretches dropped and their ends merged" *
          doctest::test_suite("unit")) {
    auto path = [](std::vector<glm::dvec2> points) {
        ink::PlotPath p;
        p.points = std::move(points);
        return p;
    };
    ink::PlotPath dot;
    dot.points = {{50, 50}};
    dot.radius = 0.2;
    // Simplification: points in line go, a repeated point goes, a zig-zag within the tolerance goes, a corner
    // stays, a zero-length path goes, a circle is left alone.
    std::vector<ink::PlotPath> paths{path({{0, 0}, {1, 0}, {2, 0}, {2, 0}, {3, 0}, {4, 0}}),   // 6 points → 2
                                     path({{0, 1}, {1, 1.01}, {2, 0.99}, {3, 1.02}, {4, 1}}),  // 5 → 2
                                     path({{0, 2}, {1, 2}, {2, 2}, {2, 3}, {2, 4}}),           // 5 → 3 (the corner)
                                     path({{5, 5}, {5, 5.0001}}),                              // zero length: dropped
                                     dot};
    CHECK(ink::simplifyPaths(paths, 0.06, 1e-3) == 4 + 3 + 2 + 2);
    REQUIRE(paths.size() == 4);
    CHECK(paths[0].points == std::vector<glm::dvec2>{{0, 0}, {4, 0}});
    CHECK(paths[1].points == std::vector<glm::dvec2>{{0, 1}, {4, 1}});
    CHECK(paths[2].points == std::vector<glm::dvec2>{{0, 2}, {2, 2}, {2, 4}});
    CHECK(paths[3].circle());

    // Retraced: a stroke that doubles back on itself keeps its way out (and a stub of at most 5 tolerances, the
    // fold a contour's cusp makes, under one and a half pen widths); a second
    // copy of a stroke, drawn the other way with other points, goes; a stroke across both stays whole, and so
    // does a closed square.
    const double tol = 0.075;  // a quarter of a 0.3 mm pen
    paths = {path({{0, 0}, {10, 0}, {0, 0}}),
             path({{0, 5}, {10, 5}}),
             path({{10, 5}, {5, 5.01}, {0, 5}}),
             path({{5, -5}, {5, 10}}),
             path({{20, 0}, {30, 0}, {30, 10}, {20, 10}, {20, 0}}),
             dot};
    const double dropped = ink::dropRetraced(paths, tol);
    REQUIRE(paths.size() == 5);
    CHECK(paths[0].points.front() == glm::dvec2(0, 0));
    CHECK(paths[0].length() > 10);
    CHECK(paths[0].length() < 10 + 5.5 * tol);
    CHECK(paths[1].points == std::vector<glm::dvec2>{{0, 5}, {10, 5}});
    CHECK(paths[2].points == std::vector<glm::dvec2>{{5, -5}, {5, 10}});
    CHECK(paths[3].points.size() == 5);
    CHECK(paths[4].circle());
    CHECK(dropped == doctest::Approx(10 - (paths[0].length() - 10) + 10.00001).epsilon(1e-3));
    // A contour's cusp: the curve folds back along itself for 0.3 mm (4 tolerances) and goes on; one stroke still
    // (cutting the fold left a gap at every cusp: the torus's inner contour came out in five pieces).
    std::vector<ink::PlotPath> cusp = {path({{0, 0}, {1, 0}, {0.7, 0.01}, {0.7, 3}})};
    CHECK(ink::dropRetraced(cusp, tol) == 0);
    REQUIRE(cusp.size() == 1);
    CHECK(cusp[0].points.size() == 4);

    // A stroke that runs along a kept one but leaves it for a moment (where the view crowds strokes of several
    // families together) leaves a sliver between its retraced stretches: a pen lift for a dot, dropped with them
    // (under kSliverTolerances tolerances, 3 pen widths); a longer excursion stays.
    std::vector<ink::PlotPath> weave = {path({{0, 0}, {10, 0}}),
                                        path({{0, 0}, {4, 0}, {4.1, 0.2}, {4.4, 0.2}, {4.5, 0}, {10, 0}}),
                                        path({{0, 0}, {4, 0}, {4.5, 1}, {5.5, 1}, {6, 0}, {10, 0}})};
    ink::dropRetraced(weave, tol);
    REQUIRE(weave.size() == 2);
    CHECK(weave[0].points == std::vector<glm::dvec2>{{0, 0}, {10, 0}});
    CHECK(weave[1].length() > 2.8);  // the excursion off the kept line: 3.24 mm, less its ends within tol
    CHECK(weave[1].length() < 3.3);
    CHECK(ink::kSliverTolerances * tol > 0.75);  // the sliver is at most 0.75 mm long

    // Strokes crossing at a shallow angle (two hatching families 45° apart on a surface the view foreshortens:
    // 20° on the page) are no retrace: both stay whole (with 30° "near parallel" the crossing was cut out).
    // Only below 15° do they count as parallel, and a crossing's covered run, 2·tol / sin 15° = 7.7·tol, is still
    // under the 8·tol a cut needs.
    const double slope = std::tan(20.0 * M_PI / 180.0);
    std::vector<ink::PlotPath> crossing = {path({{0, 0}, {10, 0}}), path({{0, -5 * slope}, {10, 5 * slope}})};
    CHECK(ink::dropRetraced(crossing, tol) == 0);
    REQUIRE(crossing.size() == 2);
    CHECK(crossing[1].points.size() == 2);

    // Merged end to end within the tolerance, reversing where needed: three strokes on a line (gaps 0.05 and
    // 0.1 mm, the middle one given backwards) become one; a stroke 10 mm away stays, and so does the dot.
    paths = {path({{0, 20}, {10, 20}}), path({{20, 20}, {10.05, 20}}), path({{-10, 20}, {-0.1, 20}}),
             path({{30, 20}, {40, 20}}), dot};
    CHECK(ink::mergeEnds(paths, 0.15, 1e-3) == 2);
    REQUIRE(paths.size() == 3);
    CHECK(paths[0].points == std::vector<glm::dvec2>{{-10, 20}, {-0.1, 20}, {0, 20}, {10, 20}, {10.05, 20}, {20, 20}});
    CHECK(paths[1].points == std::vector<glm::dvec2>{{30, 20}, {40, 20}});
    CHECK(paths[2].circle());
    CHECK(ink::simplifyPaths(paths, 0.06, 1e-3) == 4);  // the joints in line
    CHECK(paths[0].points == std::vector<glm::dvec2>{{-10, 20}, {20, 20}});
}

TEST_CASE("vector: by default a simplified curve keeps no corner a zoomed print would show" *
          doctest::test_suite("unit")) {
    // A 40 mm arc of radius 70 mm (the torus's far hole wall on an A4 page), traced in 400 points: simplified to
    // the default tolerance, its chords turn under 3° at each joint, in under 40 points. At 0.2 of the pen width
    // (0.06 mm, the default before) they turned 4.1°, in 9 points; Ramer–Douglas–Peucker's chords keep a sagitta s ≤ ε,
    // and a chord of radius R turns √(8s/R).
    const ink::PageOptions page;
    const double radius = 70, span = 40 / radius;
    ink::PlotPath arc;
    for (int i = 0; i < 400; ++i) {
        const double t = span * (i / 399.0 - 0.5);
        arc.points.emplace_back(radius * std::sin(t), radius * std::cos(t));
    }
    std::vector<ink::PlotPath> paths{arc};
    ink::simplifyPaths(paths, page.simplify * page.penWidth, 1e-3);
    REQUIRE(paths.size() == 1);
    const auto& p = paths[0].points;
    CHECK(p.size() >= 10);
    CHECK(p.size() < 40);
    double turn = 0;
    for (size_t i = 1; i + 1 < p.size(); ++i) {
        const glm::dvec2 a = glm::normalize(p[i] - p[i - 1]), b = glm::normalize(p[i + 1] - p[i]);
        turn = std::max(turn, std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180 / M_PI);
    }
    CHECK(turn < 3);
    CHECK(turn > 0.5);  // still simplified: 400 points would turn 0.1°
}

TEST_CASE("vector: ordering never lengthens the pen-up travel of the order given" * doctest::test_suite("unit")) {
    // Random strokes, and strokes already in a good order (a row drawn left to right): ordered travel is never
    // longer than the given order's.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 100);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<ink::PlotPath> paths;
        const int n = 2 + trial * 7;
        for (int i = 0; i < n; ++i) {
            ink::PlotPath p;
            glm::dvec2 a(u(rng), u(rng));
            p.points = {a, a + glm::dvec2(u(rng), u(rng)) * 0.05};
            paths.push_back(p);
        }
        if (trial % 2) {
            for (int i = 0; i < n; ++i) paths[size_t(i)].points = {{3.0 * i, 0}, {3.0 * i + 2, 0}};
        }
        const double before = ink::travel(paths, {0, 0});
        ink::orderPaths(paths, {0, 0});
        CAPTURE(trial);
        CHECK(ink::travel(paths, {0, 0}) <= before + 1e-9);
    }
}

TEST_CASE("vector: the layout reports paths, vertices, merges, lifts and the plot time of each pen" *
          doctest::test_suite("unit")) {
    // Two strokes that meet end to end (one backwards, a hundredth of a pixel apart), one of them retraced
    // twice and with points in line; a stroke far away.
    ink::VectorDrawing d;
    d.width = 200;
    d.height = 200;
    ink::VectorLayer& l = d.layer("contour", {0, 0, 0, 1});
    l.lines = {
        {{10, 10}, {50, 10}, {100, 10}}, {{150, 10}, {100.01f, 10}}, {{100, 10}, {10, 10}}, {{10, 190}, {190, 190}}};
    ink::PageOptions o;  // A4, pen 0.3
    const ink::Plot plot = ink::layoutPlot(d, o);
    REQUIRE(plot.layers.size() == 1);
    const ink::PlotLayer& layer = plot.layers[0];
    CHECK(layer.pathsBefore == 4);
    CHECK(layer.verticesBefore == 9);
    CHECK(layer.merged == 1);
    CHECK(layer.paths.size() == 2);
    CHECK(layer.vertices == 4);
    CHECK(layer.lifts == 2);
    const double scale = 180.0 / 200;  // mm a pixel
    CHECK(layer.retraced == doctest::Approx(90 * scale).epsilon(0.01));
    CHECK(layer.penDown == doctest::Approx(320 * scale).epsilon(0.001));
    CHECK(layer.travelAfter <= layer.travelBefore);
    CHECK(layer.plotSeconds == doctest::Approx(layer.penDown / 25 + layer.travelAfter / 75 + 2 * 0.15));
    CHECK(plot.drawSpeed == 25);
    CHECK(plot.travelSpeed == 75);
    CHECK(plot.liftSeconds == 0.15);
}

TEST_CASE("vector: strokes split by visibility into their layer and the hidden layer below" *
          doctest::test_suite("unit")) {
    ink::VectorDrawing d;
    d.width = d.height = 100;
    d.layer("stipple", {0, 0, 0, 1});
    ink::Stroke s;
    s.points = {{0, 0}, {10, 0}, {20, 0}, {30, 0}, {40, 0}};
    s.visible = {true, false, false, true};
    d.addStrokes("contour", {0, 0, 0, 1}, {s}, "hidden");
    REQUIRE(d.layers.size() == 3);
    CHECK(d.layers[0].name == "hidden");
    CHECK(d.layers[1].name == "stipple");
    CHECK(d.layers[2].name == "contour");
    REQUIRE(d.layers[2].lines.size() == 2);
    CHECK(d.layers[2].lines[0] == std::vector<glm::vec2>{{0, 0}, {10, 0}});
    CHECK(d.layers[2].lines[1] == std::vector<glm::vec2>{{30, 0}, {40, 0}});
    REQUIRE(d.layers[0].lines.size() == 1);
    CHECK(d.layers[0].lines[0] == std::vector<glm::vec2>{{10, 0}, {20, 0}, {30, 0}});
}

TEST_CASE("vector: the layout fits the view in the margins, sizes circles to the dots and drops what leaves it" *
          doctest::test_suite("unit")) {
    ink::VectorDrawing d;
    d.width = 200;
    d.height = 100;  // wide: a landscape page
    ink::VectorLayer& l = d.layer("stipple", {0, 0, 0, 1});
    l.dots = {{{100, 50}, 4.0f}, {{0.5f, 50}, 4.0f}, {{100, 1}, 0.5f}};
    l.lines = {{{-50, 50}, {250, 50}}};
    ink::PageOptions o;  // A4, margin 15, pen 0.3
    ink::Plot plot = ink::layoutPlot(d, o);
    CHECK(plot.width == 297);
    CHECK(plot.height == 210);
    REQUIRE(plot.layers.size() == 1);
    const ink::PlotLayer& layer = plot.layers[0];
    CHECK(layer.pen == 1);
    // 267 mm for 200 pixels: 1.335 mm a pixel; the view's top at (210 − 133.5) / 2.
    const double scale = 267.0 / 200.0, top = (210 - 100 * scale) / 2;
    std::vector<double> big, small;  // the circles' radii
    for (const ink::PlotPath& p : layer.paths) {
        if (p.circle()) {
            // Each dot one stroke of the pen, its circles outermost first.
            std::vector<double>& radii = p.points[0].y == doctest::Approx(top + 50 * scale) ? big : small;
            CHECK(radii.empty());
            if (&radii == &big) CHECK(p.points[0].x == doctest::Approx(15 + 100 * scale));
            for (uint32_t k = 0; k <= p.rings; ++k) radii.push_back(p.ringRadius(k));
            // The pen goes in along the radius and out again, and round each circle.
            double length = 2 * (radii.front() - radii.back());
            for (double r : radii) length += 2 * M_PI * r;
            CHECK(p.length() == doctest::Approx(length));
        } else {
            // The line clipped to the view, half a pen inside.
            CHECK(p.points.front().x == doctest::Approx(15.15));
            CHECK(p.points.back().x == doctest::Approx(282 - 0.15));
        }
    }
    // 5.3 and 0.67 mm wide with a 0.3 mm pen: the outer circle's stroke covers the rim, and circles 0.27 mm
    // (0.9 pens) apart fill the inside down to one within half a pen of the centre. The dot on the left edge
    // would ink outside the view.
    REQUIRE(big.size() == 10);
    CHECK(big[0] == doctest::Approx((4 * scale - 0.3) / 2));
    for (size_t i = 1; i < big.size(); ++i) CHECK(big[i - 1] - big[i] == doctest::Approx(0.27));
    CHECK(big.back() <= 0.15);
    CHECK(big[big.size() - 2] > 0.15);
    REQUIRE(small.size() == 2);
    CHECK(small[0] == doctest::Approx((0.5 * scale - 0.3) / 2));
    CHECK(small[1] == ink::kMinRadius);
    CHECK(layer.fillCircles == 10);
    CHECK(layer.lifts == 3);  // the two dots and the line, a stroke each
    CHECK(layer.widestDot == doctest::Approx(4 * scale));
    // As written: each dot's path ends where it starts, its steps between circles absolute (a thin pen's ring
    // spacing of 0.9 · 0.123 mm, rounded step by step, would drift).
    o.penWidth = 0.123;
    const std::string svg = ink::plotSvg(ink::layoutPlot(d, o));
    size_t dots = 0;
    for (size_t at = svg.find(" d=\""); at != std::string::npos; at = svg.find(" d=\"", at + 1)) {
        const std::string path = svg.substr(at + 4, svg.find('"', at + 4) - at - 4);
        if (path.find('a') == std::string::npos) continue;
        const PathShape s = shapeOf(path);
        CHECK(s.endX == s.startX);
        CHECK(s.endY == s.startY);
        ++dots;
    }
    CHECK(dots == 2);
    // A pen wider than the dots: the smallest circle.
    o.penWidth = 6;
    const ink::Plot wide = ink::layoutPlot(d, o);  // named: a range-for over a temporary's member dangles
    for (const ink::PlotPath& p : wide.layers[0].paths)
        if (p.circle()) CHECK(p.radius == ink::kMinRadius);
    o.margin = 110;
    CHECK_THROWS_WITH_AS(ink::layoutPlot(d, o), "margins of 110 mm leave no room on a 297x210 mm page", ink::Error);
    CHECK(ink::parsePageSize("letter") == glm::dvec2(215.9, 279.4));
    CHECK(ink::parsePageSize("300x200.5mm") == glm::dvec2(300, 200.5));
    CHECK_THROWS_WITH_AS(ink::parsePageSize("A9"),
                         "page 'A9' is not A3, A4, A5, letter or WxHmm with sides of 10 to 5000 mm", ink::Error);
}

TEST_CASE("vector: a silhouette's stroke is drawn round the disk it sweeps, and as a tick along it" *
          doctest::test_suite("unit")) {
    // A 200 × 100 view on A4 landscape: 1.335 mm a pixel. A dot 0.4 pixels wide swept 4 pixels each way along
    // (3, 4) / 5; one 3 pixels wide along the same.
    ink::VectorDrawing d;
    d.width = 200;
    d.height = 100;
    d.layer("stipple", {0, 0, 0, 1}).dots = {{{100, 50}, 0.4f, {2.4f, 3.2f}}, {{100, 50}, 3.0f, {2.4f, 3.2f}}};
    ink::PageOptions o;
    const double scale = 267.0 / 200.0, top = (210 - 100 * scale) / 2;
    const glm::dvec2 c(15 + 100 * scale, top + 50 * scale), axis(0.6, 0.8);
    const double half = 4 * scale;
    // The distance of q from the stroke's centre segment, and how far along and across it q lies.
    auto fromSegment = [&](glm::dvec2 q) {
        return glm::distance(q, c + std::clamp(glm::dot(q - c, axis), -half, half) * axis);
    };
    const ink::Plot plot = ink::layoutPlot(d, o);
    REQUIRE(plot.layers.size() == 1);
    REQUIRE(plot.layers[0].paths.size() == 2);
    // The thin one: a stadium whose pen's centre line lies (d − w) / 2 from the segment, closed, reaching both ends'
    // caps and both sides.
    const ink::PlotPath* thin = &plot.layers[0].paths[0];
    const ink::PlotPath* wide = &plot.layers[0].paths[1];
    if (thin->points.size() > wide->points.size()) std::swap(thin, wide);
    REQUIRE(!thin->circle());
    REQUIRE(thin->points.size() > 8);
    CHECK(glm::distance(thin->points.front(), thin->points.back()) < 1e-9);
    const double r = (0.4 * scale - o.penWidth) / 2;
    double along0 = INFINITY, along1 = -INFINITY, side0 = INFINITY, side1 = -INFINITY;
    size_t off = 0;
    for (const glm::dvec2& q : thin->points) {
        off += std::abs(fromSegment(q) - r) > 1e-6;
        const double t = glm::dot(q - c, axis), u = glm::dot(q - c, glm::dvec2(-axis.y, axis.x));
        along0 = std::min(along0, t), along1 = std::max(along1, t), side0 = std::min(side0, u),
        side1 = std::max(side1, u);
    }
    CHECK(off == 0);
    CHECK(along0 == doctest::Approx(-half - r));
    CHECK(along1 == doctest::Approx(half + r));
    CHECK(side0 == doctest::Approx(-r));
    CHECK(side1 == doctest::Approx(r));
    // Pen down: two sides and two half circles (each 6 chords).
    CHECK(thin->length() == doctest::Approx(4 * half + 2 * M_PI * r).epsilon(0.01));
    // The wide one: the same rings as a round dot's, each stretched into a stadium, outermost first.
    const double r0 = (3 * scale - o.penWidth) / 2, step = ink::kDotFillStep * o.penWidth;
    REQUIRE(wide->points.size() % 15 == 0);
    const size_t rings = wide->points.size() / 15;
    CHECK(rings == size_t(std::ceil((r0 - 0.5 * o.penWidth) / step)) + 1);
    for (size_t k = 0; k < rings; ++k)
        for (size_t i = 0; i < 15; ++i)
            CHECK(fromSegment(wide->points[15 * k + i]) ==
                  doctest::Approx(std::max(r0 - double(k) * step, ink::kMinRadius)).epsilon(1e-6));
    // Ticks: one stroke along the segment, (d − w) longer.
    o.dotStyle = ink::DotStyle::Tick;
    d.layers[0].dots.pop_back();
    const ink::Plot ticks = ink::layoutPlot(d, o);
    REQUIRE(ticks.layers[0].paths.size() == 1);
    const ink::PlotPath& tick = ticks.layers[0].paths[0];
    REQUIRE(tick.points.size() == 2);
    CHECK(glm::distance(tick.points[0], c - (half + r) * axis) < 1e-6);
    CHECK(glm::distance(tick.points[1], c + (half + r) * axis) < 1e-6);
    // A stroke whose ink would leave the view is dropped, as a dot is: 2.4 · 1.335 mm along x each way, 2.7 mm in.
    d.layers[0].dots[0].center = {2.0f, 50.0f};
    for (ink::DotStyle style : {ink::DotStyle::Tick, ink::DotStyle::Circle}) {
        o.dotStyle = style;
        CHECK(ink::layoutPlot(d, o).layers.empty());
    }
}

TEST_CASE("vector: render writes the frame's marks as SVG and PDF that independent renderers draw as the PNG" *
          doctest::test_suite("cli")) {
    TempDir dir("inkwell-vector");
    // One frame, three outputs; the page has the image's shape and no margin, so drawn at the PNG's size the
    // page is the image. 2 pixels a millimetre: the 2-pixel dots are 1 mm, filled by a 0.5 mm pen.
    const std::string common = "render " + kBunny +
                               " --control-points 200 --levels 4 --ink-density 3 --size 320 320 --page 160x160mm "
                               "--margin 0 --validation";
    Run r = runInkwell(common + " --pen-width 0.5 -o " + dir / "a.png" + " -o " + dir / "a.svg" + " -o " +
                       dir / "a.pdf" + " --stats " + dir / "a.json");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(r.output.find("pen 1 (stipple):") != std::string::npos);
    ink::RgbaImage png = ink::readPng(dir / "a.png");

    // The independent renderers come with scripts/install-deps.sh (librsvg2-bin, poppler-utils); where one is
    // missing (a machine set up otherwise), its comparison is skipped, and said so at the end.
    std::string missing;
    if (runShell("command -v rsvg-convert").status != 0) {
        missing += " rsvg-convert";
    } else {
        Run svg = runShell("rsvg-convert -w 320 -h 320 -b white -o " + dir / "svg.png" + " " + dir / "a.svg" + " 2>&1");
        REQUIRE_MESSAGE(svg.status == 0, "rsvg-convert (librsvg2-bin, scripts/install-deps.sh): " << svg.output);
        Difference ds = compareBlurred(png, ink::readPng(dir / "svg.png"));
        MESSAGE("SVG vs PNG: " << ds.fraction * 100 << "% differ; ink " << ds.inkA << " vs " << ds.inkB);
        CHECK(ds.fraction <= 0.02);
        CHECK(ds.inkA > 5000);  // a drawing, not two blank pages
        // The criterion fails a drawing two pixels off.
        Difference off = compareBlurred(png, ink::readPng(dir / "svg.png"), 2);
        MESSAGE("SVG two pixels off: " << off.fraction * 100 << "% differ");
        CHECK(off.fraction > 0.02);
        CHECK(double(ds.inkB) > 0.7 * double(ds.inkA));
        CHECK(double(ds.inkB) < 1.3 * double(ds.inkA));
    }
    if (runShell("command -v pdftoppm").status != 0) {
        missing += " pdftoppm";
    } else {
        Run pdf = runShell("pdftoppm -png -singlefile -scale-to-x 320 -scale-to-y 320 " + dir / "a.pdf" + " " +
                           dir / "pdf" + " 2>&1");
        REQUIRE_MESSAGE(pdf.status == 0, "pdftoppm (poppler-utils, scripts/install-deps.sh): " << pdf.output);
        Difference dp = compareBlurred(png, ink::readPng(dir / "pdf.png"));
        MESSAGE("PDF vs PNG: " << dp.fraction * 100 << "% differ; ink " << dp.inkA << " vs " << dp.inkB);
        CHECK(dp.fraction <= 0.02);
        CHECK(double(dp.inkB) > 0.7 * double(dp.inkA));
    }
    // The stats: the layer, its paths, travel ordered and not.
    nlohmann::json stats = nlohmann::json::parse(readFile(dir / "a.json"));
    REQUIRE(stats["vector"]["layers"].size() == 1);
    CHECK(stats["vector"]["layers"][0]["name"] == "stipple");
    CHECK(stats["vector"]["layers"][0]["paths"].get<size_t>() ==
          parseSvg(readFile(dir / "a.svg")).layers.at(0).paths.size());

    // Hidden lines, and a pen wider than the dots (the circles' stroke covers their centre): a grey layer of
    // its own below, and the picture still the PNG's.
    r = runInkwell(common + " --hidden-lines --pen-width 0.8 -o " + dir / "h.png" + " -o " + dir / "h.svg");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    ParsedSvg hidden = parseSvg(readFile(dir / "h.svg"));
    REQUIRE(hidden.layers.size() == 2);
    CHECK(hidden.layers[0].label == "1 hidden");
    CHECK(hidden.layers[1].label == "2 stipple");
    CHECK(hidden.layers[0].paths.size() > 10);
    if (!missing.empty()) {
        skipTest("not installed:" + missing + " (scripts/install-deps.sh): no independent renderer drew those files");
        return;
    }
    REQUIRE(runShell("rsvg-convert -w 320 -h 320 -b white -o " + dir / "hsvg.png" + " " + dir / "h.svg").status == 0);
    Difference dh = compareBlurred(ink::readPng(dir / "h.png"), ink::readPng(dir / "hsvg.png"));
    MESSAGE("hidden lines, SVG vs PNG: " << dh.fraction * 100 << "% differ");
    CHECK(dh.fraction <= 0.02);
}

TEST_CASE("vector: the default bunny's SVG: layers, mm, no zero-length path, inside the margins, ordered, same bytes" *
          doctest::test_suite("cli")) {
    TempDir dir("inkwell-vector");
    // The default drawing of the bunny: its default fit (fitted once here) and every default of render.
    REQUIRE(runInkwell("fit " + kBunny + " -o " + dir / "bunny.hrbf").status == 0);
    const std::string command = "render " + dir / "bunny.hrbf" + " --stats " + dir / "s.json" + " -o ";
    Run r = runInkwell(command + dir / "a.svg -o " + dir / "a.pdf");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const std::string text = readFile(dir / "a.svg");
    CHECK(text.size() < 10'000'000);
    ParsedSvg svg = parseSvg(text);
    CHECK(svg.width == "210mm");
    CHECK(svg.height == "297mm");
    CHECK(svg.viewBox == "0 0 210 297");
    CHECK(svg.elements == 0);  // nothing but the layers and their paths
    REQUIRE(svg.layers.size() == 1);
    const ParsedSvg::Layer& layer = svg.layers[0];
    CHECK(layer.groupmode == "layer");
    CHECK(layer.label == "1 stipple");
    CHECK(layer.fill == "none");
    CHECK(layer.strokeWidth == "0.3");
    CHECK(layer.paths.size() > 10000);
    size_t zeroLength = 0, outside = 0;
    const double half = 0.15, margin = 15, slack = 1e-3;  // the writer's micrometre rounding
    for (const std::string& d : layer.paths) {
        PathShape s = shapeOf(d);
        zeroLength += !(s.length > 0);
        outside += s.minX - half < margin - slack || s.minY - half < margin - slack ||
                   s.maxX + half > 210 - margin + slack || s.maxY + half > 297 - margin + slack;
    }
    CHECK(zeroLength == 0);
    CHECK(outside == 0);

    nlohmann::json stats = nlohmann::json::parse(readFile(dir / "s.json"));
    const nlohmann::json& l = stats["vector"]["layers"][0];
    double before = l["travel_before_mm"], after = l["travel_after_mm"];
    MESSAGE("pen-up travel " << before << " mm unordered, " << after << " mm ordered; pen down "
                             << l["pen_down_mm"].get<double>() << " mm");
    CHECK(after <= before / 3);
    CHECK(l["pen_down_mm"].get<double>() > 0);

    // The same command again: the same bytes, for the SVG and the PDF; and --no-order keeps the device's order.
    r = runInkwell(command + dir / "b.svg -o " + dir / "b.pdf");
    REQUIRE(r.status == 0);
    CHECK(readFile(dir / "b.svg") == text);
    CHECK(readFile(dir / "a.pdf") == readFile(dir / "b.pdf"));
    CHECK(readFile(dir / "a.pdf").rfind("%PDF-1.5\n", 0) == 0);
    REQUIRE(runInkwell(command + dir / "c.svg --no-order").status == 0);
    nlohmann::json unordered = nlohmann::json::parse(readFile(dir / "s.json"));
    CHECK(unordered["vector"]["layers"][0]["travel_after_mm"].get<double>() == doctest::Approx(before));
}

TEST_CASE("vector: a pen drawing's stats give each pen's length, travel, lifts and plot time" *
          doctest::test_suite("cli")) {
    TempDir dir("inkwell-vector");
    // The bundled bunny with every default (its fit, the 1024² view, A4, a 0.3 mm pen).
    // Without the crease lines of the bunny's coarse mesh (a pen of their own: tests/unit/test_features.cpp).
    const std::string command =
        "render " + kBunny + " --style contours+hatching --creases off --stats " + dir / "s.json";
    Run r = runInkwell(command + " -o " + dir / "x.svg");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const nlohmann::json stats = nlohmann::json::parse(readFile(dir / "s.json"));
    const nlohmann::json& vector = stats["vector"];
    CHECK(vector["pens"] == 2);  // hatching, contour
    CHECK(vector["time_model"]["pen_down_mm_per_s"] == 25.0);
    double total = 0;
    REQUIRE(vector["layers"].size() == 2);
    for (const nlohmann::json& l : vector["layers"]) {
        CAPTURE(l.dump());
        const double down = l["pen_down_mm"], travel = l["travel_after_mm"], seconds = l["plot_seconds"];
        const size_t lifts = l["lifts"], paths = l["paths"];
        // Plausible: the bunny is about 110 mm tall on the page; the hatching is metres of ink, the contour
        // tens of centimetres; each plots in seconds to minutes.
        CHECK(down > 100);
        CHECK(down < 20000);
        CHECK(seconds > 5);
        CHECK(seconds < 3600);
        CHECK(l["retraced_mm"].get<double>() >= 0);
        CHECK(lifts == paths);
        CHECK(lifts >= 1);
        CHECK(travel <= l["travel_before_mm"].get<double>());
        CHECK(l["vertices"].get<size_t>() <= l["vertices_before"].get<size_t>());
        CHECK(seconds == doctest::Approx(down / 25 + travel / 75 + 0.15 * double(lifts)));
        total += seconds;
        // The summary line on stdout: lifts and the time.
        std::string summary = "(";
        summary += l["name"].get<std::string>();
        summary += "): ";
        summary += std::to_string(paths);
        summary += " paths";
        CHECK(r.output.find(summary) != std::string::npos);
    }
    CHECK(vector["plot_seconds"].get<double>() == doctest::Approx(total));
    CHECK(r.output.find(" lifts, about ") != std::string::npos);
    // Other speeds, other times; speeds that are not are refused, writing nothing.
    REQUIRE(runInkwell(command + " -o " + dir / "y.svg --plot-speed 50 --travel-speed 150 --lift-time 0").status == 0);
    const nlohmann::json fast = nlohmann::json::parse(readFile(dir / "s.json"))["vector"];
    CHECK(fast["plot_seconds"].get<double>() < total / 2);
    for (const char* bad : {"--plot-speed 0", "--travel-speed -1", "--lift-time 100"}) {
        CAPTURE(bad);
        Run refused = runInkwell(command + " -o " + dir / "z.svg " + bad);
        CHECK(refused.status != 0);
        CHECK(refused.output.find("must be in") != std::string::npos);
        CHECK_FALSE(std::ifstream(dir / "z.svg").good());
    }
}

TEST_CASE("vector: ticks, pages and bad options" * doctest::test_suite("cli")) {
    TempDir dir("inkwell-vector");
    const std::string command = "render " + kBunny + " --control-points 100 --levels 2 --size 300 200 ";
    Run r = runInkwell(command + "--dot-style tick --page A3 --margin 20 --pen-width 0.5 -o " + dir / "t.svg");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    ParsedSvg svg = parseSvg(readFile(dir / "t.svg"));
    CHECK(svg.width == "420mm");  // a wide image: landscape
    CHECK(svg.height == "297mm");
    REQUIRE(svg.layers.size() == 1);
    CHECK(svg.layers[0].strokeWidth == "0.5");
    for (const std::string& d : svg.layers[0].paths) {
        CHECK(d.find('a') == std::string::npos);  // no circles
        PathShape s = shapeOf(d);
        CHECK(s.length > 0);
        CHECK(s.minX >= 20 - 1e-3);
    }
    r = runInkwell(command + "--orientation portrait --page 100x50mm -o " + dir / "p.svg");
    REQUIRE(r.status == 0);
    CHECK(parseSvg(readFile(dir / "p.svg")).width == "50mm");

    auto refused = [&](const std::string& args, const std::string& message) {
        Run bad = runInkwell(command + args + " -o " + dir / "x.svg");
        CHECK(bad.status != 0);
        CHECK(bad.output == "inkwell: " + message + "\n");
        CHECK_FALSE(std::filesystem::exists(dir / "x.svg"));
    };
    refused("--page B5", "page 'B5' is not A3, A4, A5, letter or WxHmm with sides of 10 to 5000 mm");
    refused("--pen-width 0", "--pen-width must be in [0.001, 10] mm (the files give a micrometre)");
    refused("--pen-width 0.0004", "--pen-width must be in [0.001, 10] mm (the files give a micrometre)");
    refused("--margin 200", "--margin must be at least 0 mm and leave room for the pen on the page");
    // Room on the page, but not for the pen: an empty drawing was written, exit 0 (issue 29).
    refused("--page 100x100mm --margin 49.9 --pen-width 0.3",
            "--margin must be at least 0 mm and leave room for the pen on the page");
}
