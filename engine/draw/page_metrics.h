// How evenly a frame's stipples lie on the page (docs/algorithm.md §4, issue 26's measure): in square windows of
// the target, each far from the outline, the mean nearest-neighbour distance of the drawn front dots over r_max =
// √(2A / (√3 N)) (the spacing of the densest hexagonal packing of the window's N dots: 1 for a lattice, 0.47 for
// white noise), the share of dots closer than r_max / 2 to another (clumped), and the ink the dots cover. What
// `render --stats` reports as `stipples[].page` and bench as `page`; tests/gpu/test_page.cpp asserts on it.
#pragma once

#include "shared/render.h"  // gpu::Dot

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ink {

struct PageWindow {
    double x0 = 0, y0 = 0;   // its corner, in the dots' pixels
    size_t dots = 0;         // drawn front dots in it
    double meanNearest = 0;  // their mean nearest-neighbour distance (to any drawn front dot) over r_max
    double clumped = 0;      // the share of them closer than r_max / 2 to another
    double coverage = 0;     // their ink (each π/4 (dotDiameter · scale)²) over the window's area
};

struct PageMetrics {
    size_t frontDots = 0;    // front dots drawn (visible; spaced ones accepted)
    size_t largerDots = 0;   // of them, drawn larger than their class's size (Dot::scale > 1)
    size_t outlineDots = 0;  // visible silhouette dots and hidden ones drawn
    std::vector<PageWindow> windows;
    // Over the windows (0 without any): the mean of their meanNearest, the smallest, the largest clumped, and the
    // least and most coverage.
    double meanNearest = 0, worstNearest = 0, worstClumped = 0, leastCoverage = 0, mostCoverage = 0;
};

// Windows of side `window` pixels a quarter side apart over a width × height target, kept when they hold at
// least `minDots` drawn front dots and no outline dot within `margin` pixels of them. `dotDiameter`: the front
// dots' diameter in the same pixels.
PageMetrics measurePage(const std::vector<gpu::Dot>& dots, uint32_t width, uint32_t height, double window,
                        double dotDiameter, double margin, size_t minDots = 20);

}  // namespace ink
