// The ranges of the drawing's values, in one table: the command line, the presets, the viewer's panel and the
// public API (Look, DrawingOptions) all check against these, and docs/usage.md quotes them (by hand: nothing
// compares the two). No Vulkan here.
#pragma once

#include "inkwell/error.h"

#include <cmath>
#include <string>

namespace inkwell {

// [lo, hi], either end open: "(0, 64] pixels".
struct Range {
    double lo, hi;
    bool openLow = false, openHigh = false;
    const char* unit = "";  // "pixels", "of the diagonal", ... (empty: a plain number)

    // In the value's own type: a float's bounds are the floats nearest them (0.1f is within [0.001, 0.1]).
    template <class T>
    constexpr bool contains(T v) const {
        return (openLow ? v > T(lo) : v >= T(lo)) && (openHigh ? v < T(hi) : v <= T(hi));  // NaN: neither
    }
    // Throws an Error "WHAT must be in RANGE" ("--tau must be in [0, 1)") when `v` is outside.
    template <class T>
    void check(T v, const std::string& what) const {
        if (!contains(v)) throw Error(what + " must be in " + text());
    }
    // "(0, 64] pixels", "[0, 1)"
    std::string text() const {
        auto number = [](double v) {
            std::string s = std::to_string(v);
            s.erase(s.find_last_not_of('0') + 1);
            if (!s.empty() && s.back() == '.') s.pop_back();
            return s;
        };
        std::string s = std::string(openLow ? "(" : "[") + number(lo) + ", " + number(hi) + (openHigh ? ")" : "]");
        return *unit ? s + " " + unit : s;
    }
};

namespace ranges {
// Dots (Look and the render style), in output pixels.
constexpr Range dotSize{0, 64, true, false, "pixels"};  // front, silhouette and hidden dots
constexpr Range tau{0, 1, false, true};                 // the silhouette threshold on |n·v|
constexpr Range toneGamma{0, 16};                       // 0 draws every front dot
constexpr Range inkDensity{0, 100};
constexpr Range hiddenOpacity{0, 1};
// Pen lines, in output pixels.
constexpr Range penWidth{0, 32, true, false, "pixels"};  // contour, hidden contour, hatching, crease, boundary
constexpr Range halo{0, 32, false, false, "pixels"};
constexpr Range hatchSpacing{0.001, 0.1, false, false, "of the diagonal"};
constexpr Range hatchFamilies{1, 3};  // an integer
// Refinement.
constexpr Range levels{0, 15};  // an integer: refinement levels after the seeds (the device's MAX_LEVELS, less one)
constexpr Range candidatesPerStipple{2, 16};
constexpr Range supersample{1, 4};  // an integer: render this many times larger and filter down
constexpr Range passes{1, 64};      // an integer
// Plots (SVG, PDF).
constexpr Range penWidthMm{0.001, 10, false, false, "mm"};  // the files give a micrometre
constexpr Range simplify{0, 1, false, false, "pen widths"};
constexpr Range retrace{0, 1, false, false, "pen widths"};
constexpr Range merge{0, 2, false, false, "pen widths"};
constexpr Range plotSpeed{0, 10000, true, false, "mm/s"};  // pen down and pen up
constexpr Range liftTime{0, 60, false, false, "s"};
}  // namespace ranges

}  // namespace inkwell
