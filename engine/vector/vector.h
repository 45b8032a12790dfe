// Drawings as vectors, for pen plotters and print: the marks of one frame (dots and polylines in the image's
// pixels, read back from the device: engine/draw/renderer.h) laid out on a physical page, each layer's paths ordered
// to keep pen-up travel short, written as SVG (an Inkscape layer a pen) or PDF (an optional-content layer a
// pen). The same input gives the same bytes. CPU only.
#pragma once

#include "vector/path_order.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace ink {

// A polyline with a visibility for each segment (contours, hatching).
struct Stroke {
    std::vector<glm::vec2> points;  // pixels
    std::vector<bool> visible;      // one a segment (points.size() − 1); empty: every segment visible
};

// Marks drawn with one pen.
struct VectorLayer {
    struct Dot {
        glm::vec2 center;    // pixels
        float diameter;      // of the ink, pixels
        glm::vec2 along{0};  // a silhouette's stroke: the disk swept from center − along to center + along
    };
    std::string name;             // "stipple", "direction", "hidden", "contour", ...
    glm::vec4 color{0, 0, 0, 1};  // RGBA; alpha blends once over the paper (the hidden lines' grey)
    std::vector<Dot> dots;
    std::vector<std::vector<glm::vec2>> lines;  // polylines of two or more points, pixels
};

// The marks of one view in the image's pixels (x right, y down, from the top-left corner): what the PNG of
// the same view shows. Layers bottom first.
struct VectorDrawing {
    uint32_t width = 0, height = 0;
    glm::vec4 paper{1, 1, 1, 1};
    std::vector<VectorLayer> layers;

    // The layer called `name`; made with `color` when there is none, on top of the others, or below them all
    // when `below` (hidden lines).
    VectorLayer& layer(const std::string& name, glm::vec4 color, bool below = false);
    // The entry point for strokes: each stroke's runs of visible segments go to layer `name` as polylines,
    // its runs of hidden ones to layer `hiddenName` (below the others; dropped when the name is empty).
    void addStrokes(const std::string& name, glm::vec4 color, const std::vector<Stroke>& strokes,
                    const std::string& hiddenName = {}, glm::vec4 hiddenColor = {0, 0, 0, 0.45f});
};

enum class DotStyle { Circle, Tick };
enum class Orientation { Auto, Portrait, Landscape };

// The page and the pen. The view (the whole image, as the PNG frames it) is scaled to fit within the margins
// and centred.
struct PageOptions {
    double width = 210, height = 297;             // mm (A4), before orientation
    Orientation orientation = Orientation::Auto;  // Auto: landscape when the image is wider than tall
    double margin = 15;                           // mm on every side
    double penWidth = 0.3;                        // mm: every path's stroke width
    DotStyle dotStyle = DotStyle::Circle;
    bool order = true;  // order each layer's paths for short pen-up travel (and merge polylines end to end)
    // Pen lines before they are written, as fractions of the pen width: simplified (Ramer–Douglas–Peucker) to
    // `simplify`, stretches retraced within `retrace` of one already drawn dropped, ends within `merge` joined
    // (with `order` only). Dots are left as they are.
    double simplify = 0.05, retrace = 0.25, merge = 0.5;
    // The plot-time model: pen-down and pen-up (travel) speeds, mm/s, and the time of one lift (up and down).
    double drawSpeed = 25, travelSpeed = 75, liftSeconds = 0.15;
};

// "A4", "A3", "letter" (any case) or "WxHmm" (e.g. "300x200mm"); throws ink::Error naming the text.
glm::dvec2 parsePageSize(const std::string& text);

struct PlotLayer {
    std::string name;
    uint32_t pen = 1;    // 1, 2, ... bottom layer first
    glm::vec3 color{0};  // the layer's colour blended over the paper
    std::vector<PlotPath> paths;
    double travelBefore = 0, travelAfter = 0, penDown = 0;  // mm; travel from the page's top-left corner
    // Before the pen lines were simplified, merged and ordered (the marks as clipped, in the device's order),
    // and as written.
    size_t pathsBefore = 0, verticesBefore = 0, vertices = 0;
    size_t merged = 0;       // end-to-end joins
    double retraced = 0;     // pen-down length dropped as retraced, mm
    size_t lifts = 0;        // pen lifts: one a path
    double plotSeconds = 0;  // penDown / drawSpeed + travelAfter / travelSpeed + lifts · liftSeconds
    // The circles (a silhouette stroke's stadiums) inside dots more than two pen widths across that fill them
    // (PlotPath::rings, in the dots' own paths); the widest dot, mm.
    size_t fillCircles = 0;
    double widestDot = 0;
};

// A drawing laid out on a page: every path in millimetres from the page's top-left corner.
struct Plot {
    double width = 0, height = 0, penWidth = 0;
    double drawSpeed = 0, travelSpeed = 0, liftSeconds = 0;  // the time model (PageOptions)
    std::vector<PlotLayer> layers;                           // the non-empty ones
};

// Lays `drawing` out on the page: a dot becomes a circle whose stroke covers the dot (radius (d − w)/2 for a
// dot d mm wide and a pen w mm wide, at least kMinRadius; more than two pens wide, concentric circles
// kDotFillStep pens apart inside it too, down to one within half a pen of its centre) or a tick (a 45° stroke (d − w)
// long, at least 2·kMinRadius); polylines are clipped to the view; marks whose ink would leave the view are dropped;
// each layer's polylines are simplified, their retraced stretches dropped and (options.order) their ends merged
// (PageOptions::simplify, retrace, merge), then the layer's paths are ordered (options.order), touching
// polylines joined and the plot time estimated. Throws ink::Error for a
// page whose margins leave no room for the pen (the view, scaled into the margins, must be wider and taller
// than the pen) or a pen width outside [kMinPenWidth, kMaxPenWidth] mm.
Plot layoutPlot(const VectorDrawing& drawing, const PageOptions& options);
constexpr double kDotFillStep = 0.9;  // pens between a wide dot's concentric circles (a little overlap)
// The pen widths a page takes, mm: numbers are written with 3 decimals (a micrometre), so a thinner pen would
// be written as 0 (SVG: no stroke; PDF: the thinnest line the device can draw).
constexpr double kMinPenWidth = 0.001, kMaxPenWidth = 10;

std::string plotSvg(const Plot& plot);
std::string plotPdf(const Plot& plot);
// Writes `plot` as SVG or PDF, by the extension of `path` (.svg, .pdf, any case), atomically.
void writePlot(const std::string& path, const Plot& plot);
// True for a path ending in .svg or .pdf (any case).
bool isVectorPath(const std::string& path);

}  // namespace ink
