// Image comparison for regression tests and `inkwell compare`: how many pixels differ by more than a
// per-channel threshold, and a diff image that shows where.
#pragma once

#include "base/image.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace ink {

// The defaults of `inkwell compare` and of the golden tests (docs/capture.md says why these values).
constexpr uint8_t kCompareThreshold = 8;        // a pixel differs if any channel differs by more than this
constexpr double kCompareMaxFraction = 0.0025;  // at most this fraction of the pixels may differ

struct CompareResult {
    uint32_t maxAbsDiff = 0;       // largest per-channel difference, over all pixels and channels (RGBA)
    double differingFraction = 0;  // differingPixels / pixels
    size_t differingPixels = 0;
    size_t pixels = 0;     // of the images, or of the larger one when their sizes differ
    bool sameSize = true;  // when false, every pixel counts as differing (fraction 1, diff 255)
};

// The pixels of an image held elsewhere (an RgbaImage's, or the public Image's), read in place.
struct PixelsView {
    uint32_t width = 0, height = 0;
    const uint8_t* rgba = nullptr;  // width × height × 4 bytes
};
inline PixelsView view(const RgbaImage& image) { return {image.width, image.height, image.pixels.data()}; }

CompareResult compareImages(PixelsView a, PixelsView b, uint8_t threshold);
inline CompareResult compareImages(const RgbaImage& a, const RgbaImage& b, uint8_t threshold) {
    return compareImages(view(a), view(b), threshold);
}
// True when the images have the same size and at most maxFraction of their pixels differ.
bool withinTolerance(const CompareResult& result, double maxFraction);
// "max abs diff 37, 0.412% pixels differ (4321 of 1048576)"
std::string describe(const CompareResult& result);

// Differing pixels in red over a faded grey copy of `a` (after filament's renderdiff), so the changes stand
// out while the drawing stays recognisable. Images of different sizes give the union of both sizes, with
// the pixels outside either image red.
RgbaImage diffImage(PixelsView a, PixelsView b, uint8_t threshold);
inline RgbaImage diffImage(const RgbaImage& a, const RgbaImage& b, uint8_t threshold) {
    return diffImage(view(a), view(b), threshold);
}

}  // namespace ink
