#include "vector/vector.h"

#include "base/common.h"
#include "base/files.h"
#include "base/image.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>

namespace ink {

VectorLayer& VectorDrawing::layer(const std::string& name, glm::vec4 color, bool below) {
    for (VectorLayer& l : layers)
        if (l.name == name) return l;
    VectorLayer l;
    l.name = name;
    l.color = color;
    return *layers.insert(below ? layers.begin() : layers.end(), std::move(l));
}

void VectorDrawing::addStrokes(const std::string& name, glm::vec4 color, const std::vector<Stroke>& strokes,
                               const std::string& hiddenName, glm::vec4 hiddenColor) {
    // Both layers made first: making one may move the other.
    if (!hiddenName.empty()) layer(hiddenName, hiddenColor, true);
    layer(name, color);
    VectorLayer* shown = &layer(name, color);
    VectorLayer* hidden = hiddenName.empty() ? nullptr : &layer(hiddenName, hiddenColor);
    for (const Stroke& s : strokes) {
        std::vector<glm::vec2> run;
        bool runVisible = true;
        auto flush = [&] {
            VectorLayer* target = runVisible ? shown : hidden;
            if (run.size() >= 2 && target) target->lines.push_back(run);
            run.clear();
        };
        for (size_t i = 0; i + 1 < s.points.size(); ++i) {
            bool visible = s.visible.empty() || (i < s.visible.size() && s.visible[i]);
            if (!run.empty() && visible != runVisible) flush();
            runVisible = visible;
            if (run.empty()) run.push_back(s.points[i]);
            run.push_back(s.points[i + 1]);
        }
        flush();
    }
}

glm::dvec2 parsePageSize(const std::string& text) {
    std::string lower;
    for (char c : text) lower += char(std::tolower(static_cast<unsigned char>(c)));
    if (lower == "a4") return {210, 297};
    if (lower == "a3") return {297, 420};
    if (lower == "a5") return {148, 210};
    if (lower == "letter") return {215.9, 279.4};
    if (lower.size() > 2 && lower.compare(lower.size() - 2, 2, "mm") == 0) {
        size_t x = lower.find('x');
        if (x != std::string::npos) {
            std::string w = lower.substr(0, x), h = lower.substr(x + 1, lower.size() - x - 3);
            char* end = nullptr;
            double width = std::strtod(w.c_str(), &end);
            bool okW = !w.empty() && *end == '\0';
            double height = std::strtod(h.c_str(), &end);
            bool okH = !h.empty() && *end == '\0';
            if (okW && okH && width >= 10 && height >= 10 && width <= 5000 && height <= 5000) return {width, height};
        }
    }
    throw Error("page '" + text + "' is not A3, A4, A5, letter or WxHmm with sides of 10 to 5000 mm");
}

namespace {

// Liang–Barsky: the part of segment a–b inside [lo, hi], as parameters t0 ≤ t1; false when none.
bool clipSegment(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi, double& t0, double& t1) {
    t0 = 0, t1 = 1;
    glm::dvec2 d = b - a;
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0) {
            if (q[k] < 0) return false;
        } else {
            double t = q[k] / p[k];
            if (p[k] < 0)
                t0 = std::max(t0, t);
            else
                t1 = std::min(t1, t);
        }
    }
    return t0 <= t1;
}

constexpr double kResolution = 1e-3;  // mm: coordinates are written in micrometres

// Polyline `line` (mm) clipped to [lo, hi], as runs without repeated points; runs shorter than the
// resolution are dropped (they would be zero-length paths once written).
void addClipped(const std::vector<glm::dvec2>& line, glm::dvec2 lo, glm::dvec2 hi, std::vector<PlotPath>& out) {
    PlotPath run;
    auto flush = [&] {
        if (run.points.size() >= 2 && run.length() >= kResolution) out.push_back(std::move(run));
        run = {};
    };
    auto add = [&](glm::dvec2 p) {
        if (run.points.empty() || glm::distance(run.points.back(), p) >= kResolution) run.points.push_back(p);
    };
    for (size_t i = 0; i + 1 < line.size(); ++i) {
        double t0, t1;
        if (!clipSegment(line[i], line[i + 1], lo, hi, t0, t1)) {
            flush();
            continue;
        }
        glm::dvec2 a = line[i] + (line[i + 1] - line[i]) * t0, b = line[i] + (line[i + 1] - line[i]) * t1;
        if (t0 > 0) flush();
        add(a);
        add(b);
        if (t1 < 1) flush();
    }
    flush();
}

// A number in millimetres (or any unit) to the micrometre, without trailing zeros: "12.5", "-0.03", "7".
void appendNumber(std::string& out, double value, int decimals = 3) {
    long long scale = 1;
    for (int i = 0; i < decimals; ++i) scale *= 10;
    long long v = std::llround(value * double(scale));
    if (v < 0) {
        out += '-';
        v = -v;
    }
    out += std::to_string(v / scale);
    long long frac = v % scale;
    if (frac == 0) return;
    char digits[24];
    std::snprintf(digits, sizeof digits, "%0*lld", decimals, frac);
    std::string f(digits);
    while (!f.empty() && f.back() == '0') f.pop_back();
    out += '.';
    out += f;
}

std::string hexColor(glm::vec3 c) {
    char text[8];
    auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
    return text;
}

std::string xmlEscape(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '&')
            out += "&amp;";
        else if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

// Appends the closed outline of the disk of radius r swept from c − along to c + along (a stadium): along one
// side, round the far end, back along the other side and round the near end, kStadiumArc segments an end.
void appendStadium(std::vector<glm::dvec2>& points, glm::dvec2 c, glm::dvec2 along, double r) {
    constexpr int kStadiumArc = 6;
    const glm::dvec2 a = glm::normalize(along), side(-a.y, a.x);
    for (int end = 0; end < 2; ++end) {
        const double sign = end == 0 ? 1.0 : -1.0;
        const glm::dvec2 centre = c + sign * along;
        for (int i = 0; i <= kStadiumArc; ++i) {
            const double t = M_PI * double(i) / kStadiumArc;
            points.push_back(centre + sign * r * (side * std::cos(t) + a * std::sin(t)));
        }
    }
    points.push_back(points[points.size() - 2 * (kStadiumArc + 1)]);  // closed where this ring began
}

}  // namespace

Plot layoutPlot(const VectorDrawing& drawing, const PageOptions& o) {
    if (drawing.width == 0 || drawing.height == 0) throw Error("a vector drawing needs a view of at least 1x1 pixels");
    if (!(o.penWidth >= kMinPenWidth && o.penWidth <= kMaxPenWidth)) {
        char text[128];
        std::snprintf(text, sizeof text, "the pen width %g mm is not in [%g, %g] mm", o.penWidth, kMinPenWidth,
                      kMaxPenWidth);
        throw Error(text);
    }
    if (!(o.margin >= 0)) throw Error("the margin must not be negative");
    if (!(o.drawSpeed > 0 && o.travelSpeed > 0 && o.liftSeconds >= 0 && std::isfinite(o.drawSpeed) &&
          std::isfinite(o.travelSpeed) && std::isfinite(o.liftSeconds)))
        throw Error("plot speeds must be positive and the lift time not negative");
    if (!(o.simplify >= 0 && o.simplify <= 1 && o.retrace >= 0 && o.retrace <= 1 && o.merge >= 0 && o.merge <= 2))
        throw Error(
            "the simplification (0-1), retrace (0-1) and merge (0-2) tolerances are fractions of the pen width");
    glm::dvec2 page(o.width, o.height);
    const bool landscape =
        o.orientation == Orientation::Auto ? drawing.width > drawing.height : o.orientation == Orientation::Landscape;
    if (landscape != (page.x > page.y) && page.x != page.y) std::swap(page.x, page.y);
    glm::dvec2 room = page - 2.0 * o.margin;
    if (!(room.x > 0 && room.y > 0)) {
        char text[128];
        std::snprintf(text, sizeof text, "margins of %g mm leave no room on a %gx%g mm page", o.margin, page.x, page.y);
        throw Error(text);
    }
    const glm::dvec2 image(drawing.width, drawing.height);
    const double scale = std::min(room.x / image.x, room.y / image.y);  // mm a pixel
    const glm::dvec2 lo = (page - image * scale) * 0.5, hi = lo + image * scale;
    const double w = o.penWidth;
    // A view no wider or taller than the pen would hold no mark: an empty drawing, written as if it were one.
    if (!(hi.x - lo.x > w && hi.y - lo.y > w)) {
        char text[192];
        std::snprintf(text, sizeof text,
                      "margins of %g mm leave no room for a %g mm pen on a %gx%g mm page (the view would be %.3gx%.3g "
                      "mm)",
                      o.margin, w, page.x, page.y, hi.x - lo.x, hi.y - lo.y);
        throw Error(text);
    }

    Plot plot;
    plot.width = page.x;
    plot.height = page.y;
    plot.penWidth = w;
    plot.drawSpeed = o.drawSpeed;
    plot.travelSpeed = o.travelSpeed;
    plot.liftSeconds = o.liftSeconds;
    for (const VectorLayer& layer : drawing.layers) {
        PlotLayer out;
        out.name = layer.name;
        float a = layer.color.a;
        out.color = glm::vec3(layer.color) * a + glm::vec3(drawing.paper) * (1.0f - a);
        // Ink may reach the view's edge and no further: a path's centre line stays half a pen inside.
        const double eps = 1e-6;
        for (const VectorLayer::Dot& dot : layer.dots) {
            glm::dvec2 c = lo + glm::dvec2(dot.center) * scale;
            const double diameter = double(dot.diameter) * scale;
            double half = std::max((diameter - w) * 0.5, kMinRadius);
            // A silhouette's stroke: its tick lies along the stroke, (d − w) longer than it.
            const glm::dvec2 along = glm::dvec2(dot.along) * scale;
            const bool stroke = glm::length(along) > 1e-9;
            const glm::dvec2 tick = stroke ? along + glm::normalize(along) * half
                                           : glm::dvec2(1.0, -1.0) * (half / std::sqrt(2.0));  // "/", y down
            glm::dvec2 reach =
                o.dotStyle == DotStyle::Circle ? glm::abs(along) + half + 0.5 * w : glm::abs(tick) + 0.5 * w;
            if (glm::any(glm::lessThan(c - reach, lo - eps)) || glm::any(glm::greaterThan(c + reach, hi + eps)))
                continue;
            out.widestDot = std::max(out.widestDot, diameter);
            if (o.dotStyle == DotStyle::Tick) {
                out.paths.push_back({{c - tick, c + tick}});
                continue;
            }
            // A circle whose stroke covers the dot's rim; inside one wider than two pens, concentric circles
            // kDotFillStep pens apart, the last within half a pen of the centre, fill it in the same stroke.
            PlotPath p;
            p.points = {c};
            p.radius = half;
            p.ringStep = kDotFillStep * w;
            while (p.radius - p.rings * p.ringStep > 0.5 * w + 1e-9) ++p.rings;
            out.fillCircles += p.rings;
            if (stroke) {
                // The same rings stretched along the stroke (stadiums), one closed polyline.
                PlotPath rings;
                for (uint32_t k = 0; k <= p.rings; ++k) appendStadium(rings.points, c, along, p.ringRadius(k));
                p = std::move(rings);
            }
            out.paths.push_back(std::move(p));
        }
        const glm::dvec2 inset(std::min(0.5 * w, 0.5 * (hi.x - lo.x)), std::min(0.5 * w, 0.5 * (hi.y - lo.y)));
        std::vector<PlotPath> lines;
        for (const auto& line : layer.lines) {
            std::vector<glm::dvec2> mm;
            for (glm::vec2 p : line) mm.push_back(lo + glm::dvec2(p) * scale);
            addClipped(mm, lo + inset, hi - inset, lines);
        }
        if (out.paths.empty() && lines.empty()) continue;
        const glm::dvec2 home(0, 0);  // a plotter's home: the page's top-left corner
        {
            std::vector<PlotPath> given = out.paths;
            given.insert(given.end(), lines.begin(), lines.end());
            out.travelBefore = travel(given, home);
            out.pathsBefore = given.size();
            for (const PlotPath& p : given) out.verticesBefore += p.circle() ? 1 : p.points.size();
        }
        // Pen lines as a plotter wants them: retraced stretches dropped, ends merged, then simplified (the
        // joints may leave points in line). Dots are not merged: that would draw lines from dot to dot.
        const double retrace = std::max(o.retrace * w, kResolution);
        out.retraced = o.retrace > 0 ? dropRetraced(lines, retrace) : 0;
        if (o.order) out.merged = mergeEnds(lines, o.merge * w, kResolution);
        simplifyPaths(lines, o.simplify * w, kResolution);
        // Simplified lines move by up to the tolerance, and a merge may put a copy first: once more.
        if (o.retrace > 0) {
            out.retraced += dropRetraced(lines, retrace);
            if (o.order) out.merged += mergeEnds(lines, o.merge * w, kResolution);
        }
        out.paths.insert(out.paths.end(), std::make_move_iterator(lines.begin()), std::make_move_iterator(lines.end()));
        if (out.paths.empty()) continue;
        if (o.order) orderPaths(out.paths, home);
        mergeTouching(out.paths, kResolution);
        out.travelAfter = travel(out.paths, home);
        for (const PlotPath& p : out.paths) {
            out.penDown += p.length();
            out.vertices += p.circle() ? 1 : p.points.size();
        }
        out.lifts = out.paths.size();
        out.plotSeconds =
            out.penDown / o.drawSpeed + out.travelAfter / o.travelSpeed + double(out.lifts) * o.liftSeconds;
        out.pen = uint32_t(plot.layers.size() + 1);
        plot.layers.push_back(std::move(out));
    }
    return plot;
}

std::string plotSvg(const Plot& plot) {
    std::string s;
    s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += "<svg xmlns=\"http://www.w3.org/2000/svg\" "
         "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" version=\"1.1\" width=\"";
    appendNumber(s, plot.width);
    s += "mm\" height=\"";
    appendNumber(s, plot.height);
    s += "mm\" viewBox=\"0 0 ";
    appendNumber(s, plot.width);
    s += ' ';
    appendNumber(s, plot.height);
    s += "\">\n";
    for (const PlotLayer& layer : plot.layers) {
        s += "<g inkscape:groupmode=\"layer\" id=\"layer" + std::to_string(layer.pen) + "\" inkscape:label=\"" +
             std::to_string(layer.pen) + " " + xmlEscape(layer.name) + "\" fill=\"none\" stroke=\"" +
             hexColor(layer.color) + "\" stroke-width=\"";
        appendNumber(s, plot.penWidth);
        s += "\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
        for (const PlotPath& p : layer.paths) {
            s += "<path d=\"M";
            glm::dvec2 a = p.start();
            appendNumber(s, a.x);
            s += ' ';
            appendNumber(s, a.y);
            if (p.circle()) {
                // Each circle two half circles from its leftmost point back to it, the rings innermost first with
                // steps along the radius (`H` to the next leftmost point) between them (PlotPath). Not closed with `z`:
                // cairo (rsvg-convert, Inkscape) strokes a closed circle narrower than its pen as a ring with a hole,
                // while the open one, with round caps, is drawn as the disk the pen makes.
                for (uint32_t k = p.rings + 1; k-- > 0;) {
                    const double r = p.ringRadius(k);
                    if (k != 0 || p.rings != 0) {  // absolute: rounded relative steps would add up
                        s += 'H';
                        appendNumber(s, p.points[0].x - r);
                    }
                    for (double dx : {2.0 * r, -2.0 * r}) {
                        s += 'a';
                        appendNumber(s, r);
                        s += ' ';
                        appendNumber(s, r);
                        s += " 0 1 0 ";
                        appendNumber(s, dx);
                        s += " 0";
                    }
                }
            } else {
                s += 'L';
                for (size_t i = 1; i < p.points.size(); ++i) {
                    if (i > 1) s += ' ';
                    appendNumber(s, p.points[i].x);
                    s += ' ';
                    appendNumber(s, p.points[i].y);
                }
            }
            s += "\"/>\n";
        }
        s += "</g>\n";
    }
    s += "</svg>\n";
    return s;
}

std::string plotPdf(const Plot& plot) {
    constexpr double kPoints = 72.0 / 25.4;  // PDF points a millimetre
    // The page's content in millimetres, y down (the matrix flips it), each layer marked as optional content.
    std::string c = "q\n";
    appendNumber(c, kPoints, 6);
    c += " 0 0 ";
    appendNumber(c, -kPoints, 6);
    c += " 0 ";
    appendNumber(c, plot.height * kPoints);
    c += " cm\n1 J 1 j ";
    appendNumber(c, plot.penWidth);
    c += " w\n";
    auto point = [&](glm::dvec2 p, const char* op) {
        appendNumber(c, p.x);
        c += ' ';
        appendNumber(c, p.y);
        c += op;
    };
    for (const PlotLayer& layer : plot.layers) {
        c += "/OC /L" + std::to_string(layer.pen) + " BDC\n";
        for (int k = 0; k < 3; ++k) {
            appendNumber(c, layer.color[k]);
            c += ' ';
        }
        c += "RG\n";
        for (const PlotPath& p : layer.paths) {
            if (p.circle()) {
                // Each circle four cubic Béziers from its leftmost point (y down: up the page first, then
                // clockwise), the rings innermost first with steps along the radius between them, as in the SVG.
                const glm::dvec2 o = p.points[0];
                point(p.start(), " m ");
                for (uint32_t ring = p.rings + 1; ring-- > 0;) {
                    const double r = p.ringRadius(ring), k = 0.5522847498307936 * r;
                    if (ring != 0 || p.rings != 0) point(o + glm::dvec2(-r, 0), " l ");
                    point(o + glm::dvec2(-r, -k), " ");
                    point(o + glm::dvec2(-k, -r), " ");
                    point(o + glm::dvec2(0, -r), " c ");
                    point(o + glm::dvec2(k, -r), " ");
                    point(o + glm::dvec2(r, -k), " ");
                    point(o + glm::dvec2(r, 0), " c ");
                    point(o + glm::dvec2(r, k), " ");
                    point(o + glm::dvec2(k, r), " ");
                    point(o + glm::dvec2(0, r), " c ");
                    point(o + glm::dvec2(-k, r), " ");
                    point(o + glm::dvec2(-r, k), " ");
                    point(o + glm::dvec2(-r, 0), " c ");
                }
                c += "S\n";  // not closed: as in the SVG
            } else {
                point(p.points[0], " m");
                for (size_t i = 1; i < p.points.size(); ++i) {
                    c += ' ';
                    point(p.points[i], " l");
                }
                c += " S\n";
            }
        }
        c += "EMC\n";
    }
    c += "Q\n";
    const std::string stream = deflateZlib(c);

    // Objects: 1 catalog, 2 page tree, 3 page, 4 content, then one optional content group a layer.
    std::vector<std::string> objects;
    std::string groups, properties;
    for (size_t i = 0; i < plot.layers.size(); ++i) {
        const PlotLayer& layer = plot.layers[i];
        std::string name = std::to_string(layer.pen) + " " + layer.name, escaped;
        for (char ch : name) {
            if (ch == '(' || ch == ')' || ch == '\\') escaped += '\\';
            escaped += ch;
        }
        std::string ref = std::to_string(5 + i) + " 0 R";
        groups += (i ? " " : "") + ref;
        properties += "/L" + std::to_string(layer.pen) + " " + ref + " ";
        objects.push_back("<< /Type /OCG /Name (" + escaped + ") >>");
    }
    std::string size;
    appendNumber(size, plot.width * kPoints);
    size += ' ';
    appendNumber(size, plot.height * kPoints);
    objects.insert(objects.begin(), {"<< /Type /Catalog /Pages 2 0 R /OCProperties << /OCGs [" + groups +
                                         "] /D << /Order [" + groups + "] /ON [" + groups + "] >> >> >>",
                                     "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
                                     "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + size +
                                         "] /Resources << /Properties << " + properties + ">> >> /Contents 4 0 R >>",
                                     "<< /Length " + std::to_string(stream.size()) +
                                         " /Filter /FlateDecode >>\nstream\n" + stream + "\nendstream"});
    std::string pdf = "%PDF-1.5\n%\xe2\xe3\xcf\xd3\n";
    std::vector<size_t> offsets;
    for (size_t i = 0; i < objects.size(); ++i) {
        offsets.push_back(pdf.size());
        pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
    }
    const size_t xref = pdf.size();
    pdf += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
    for (size_t offset : offsets) {
        char line[24];
        std::snprintf(line, sizeof line, "%010zu 00000 n \n", offset);
        pdf += line;
    }
    pdf += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root 1 0 R >>\nstartxref\n" +
           std::to_string(xref) + "\n%%EOF\n";
    return pdf;
}

static bool endsWith(const std::string& path, const char* extension) {
    std::string lower;
    for (char c : path) lower += char(std::tolower(static_cast<unsigned char>(c)));
    std::string e(extension);
    return lower.size() > e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0;
}

bool isVectorPath(const std::string& path) { return endsWith(path, ".svg") || endsWith(path, ".pdf"); }

void writePlot(const std::string& path, const Plot& plot) {
    if (endsWith(path, ".svg"))
        writeFileAtomically(path, plotSvg(plot));
    else if (endsWith(path, ".pdf"))
        writeFileAtomically(path, plotPdf(plot));
    else
        throw Error("'" + path + "' is not an .svg or .pdf file");
}

}  // namespace ink
