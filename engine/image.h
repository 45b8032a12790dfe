// RGBA images in memory and as PNG files (written atomically, files.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ink {

struct RgbaImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;  // RGBA8, rows top to bottom
};

void writePng(const std::string& path, const RgbaImage& image);
RgbaImage readPng(const std::string& path);

// Box-filters an image whose sides are `factor` times larger.
RgbaImage downsample(const RgbaImage& image, uint32_t factor);

}  // namespace ink
