// Pen paths on a page and their order: a plotter lifts the pen between paths and travels to the next one's
// start, so the order of a layer's paths decides how long it takes. CPU only.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace ink {

// A path the pen draws in one stroke, in millimetres on the page (x right, y down): a polyline of two or more
// points, or (radius > 0) a closed circle around points[0], started and ended at its leftmost point.
struct PlotPath {
    std::vector<glm::dvec2> points;
    double radius = 0;

    bool circle() const { return radius > 0; }
    glm::dvec2 start() const { return circle() ? points[0] - glm::dvec2(radius, 0) : points.front(); }
    glm::dvec2 end() const { return circle() ? start() : points.back(); }
    double length() const;  // pen-down length
    void reverse();         // a polyline drawn the other way; a circle is its own reverse
};

// Pen-up travel of drawing `paths` in order, starting at `home`: the sum of the distances from one path's end
// to the next one's start (the way back home not counted).
double travel(const std::vector<PlotPath>& paths, glm::dvec2 home);

// Orders `paths` (reversing polylines where that helps) to shorten the pen-up travel from `home`: greedy
// nearest neighbour over a uniform grid of the free path ends, then passes of 2-opt moves (reversing a run of
// paths) between each path end and its 8 nearest path ends, until a pass gains less than 0.1% of the travel.
// 50,000 random dots take about 0.3 s on a loaded 2-core machine. The result depends only on the input.
void orderPaths(std::vector<PlotPath>& paths, glm::dvec2 home);

// Joins consecutive polylines whose end and start lie within `tolerance` (touching strokes become one stroke).
void mergeTouching(std::vector<PlotPath>& paths, double tolerance);

}  // namespace ink
