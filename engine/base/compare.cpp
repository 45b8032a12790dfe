#include "base/compare.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace ink {

namespace {

// The largest per-channel difference of the pixels at byte offsets i of a and j of b.
uint32_t pixelDiff(PixelsView a, size_t i, PixelsView b, size_t j) {
    uint32_t d = 0;
    for (size_t c = 0; c < 4; ++c) d = std::max(d, uint32_t(std::abs(int(a.rgba[i + c]) - int(b.rgba[j + c]))));
    return d;
}

size_t pixelCount(uint32_t width, uint32_t height) { return size_t(width) * height; }

}  // namespace

CompareResult compareImages(PixelsView a, PixelsView b, uint8_t threshold) {
    CompareResult r;
    if (a.width != b.width || a.height != b.height) {
        // Nothing lines up: report the worst so that no tolerance lets it pass.
        r.sameSize = false;
        r.pixels = std::max(pixelCount(a.width, a.height), pixelCount(b.width, b.height));
        r.differingPixels = r.pixels;
        r.differingFraction = 1.0;
        r.maxAbsDiff = 255;
        return r;
    }
    r.pixels = pixelCount(a.width, a.height);
    for (size_t i = 0; i < r.pixels * 4; i += 4) {
        uint32_t d = pixelDiff(a, i, b, i);
        r.maxAbsDiff = std::max(r.maxAbsDiff, d);
        if (d > threshold) ++r.differingPixels;
    }
    r.differingFraction = r.pixels ? double(r.differingPixels) / double(r.pixels) : 0.0;
    return r;
}

bool withinTolerance(const CompareResult& result, double maxFraction) {
    return result.sameSize && result.differingFraction <= maxFraction;
}

std::string describe(const CompareResult& result) {
    char line[160];
    std::snprintf(line, sizeof line, "max abs diff %u, %.3f%% pixels differ (%zu of %zu)", result.maxAbsDiff,
                  100.0 * result.differingFraction, result.differingPixels, result.pixels);
    return line;
}

RgbaImage diffImage(PixelsView a, PixelsView b, uint8_t threshold) {
    RgbaImage out;
    out.width = std::max(a.width, b.width);
    out.height = std::max(a.height, b.height);
    out.pixels.resize(pixelCount(out.width, out.height) * 4);
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x) {
            uint8_t* p = &out.pixels[(size_t(y) * out.width + x) * 4];
            bool inA = x < a.width && y < a.height, inB = x < b.width && y < b.height;
            size_t i = (size_t(y) * a.width + x) * 4, j = (size_t(y) * b.width + x) * 4;
            if (inA && inB && pixelDiff(a, i, b, j) <= threshold) {
                // Luma of a, faded three quarters of the way to white: context, not content.
                uint32_t luma = (77u * a.rgba[i] + 150u * a.rgba[i + 1] + 29u * a.rgba[i + 2]) >> 8;
                uint8_t grey = uint8_t(255 - (255 - luma) / 4);
                p[0] = p[1] = p[2] = grey;
            } else {
                p[0] = 255;
                p[1] = p[2] = 0;
            }
            p[3] = 255;
        }
    return out;
}

}  // namespace ink
