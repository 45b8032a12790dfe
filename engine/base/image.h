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
// The same from `width` × `height` RGBA8 pixels held elsewhere (the public Image's), not copied.
void writePng(const std::string& path, uint32_t width, uint32_t height, const uint8_t* rgba);
// Limits on every image read, checked from the header before anything is decoded (a small PNG may claim
// a huge size: a decompression bomb). Messages are printable ASCII whatever the file name or stb says.
constexpr uint64_t kMaxImageSide = 16384;
// 2^26 pixels (8192², the largest image Inkwell writes): 256 MiB of RGBA, so that `compare`'s two images and
// their diff stay within about 1 GB (at 2^28, two 1-bit 16384² PNGs of 300 KB took 4.2 GB).
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;
// Above 2^22 pixels, at most this many bytes of RGBA per byte of file: 4 x 1032, deflate's largest ratio.
constexpr uint64_t kMaxImageExpansion = 4 * 1032;
constexpr uint64_t kMinImageForRatio = uint64_t(1) << 22;
RgbaImage readPng(const std::string& path);
// The same on a PNG file's bytes; `name` is used in messages.
RgbaImage readPngFromMemory(const std::string& bytes, const std::string& name);

// `bytes` compressed as a zlib stream (RFC 1950; PNG's and PDF's FlateDecode), by stb's deflate.
std::string deflateZlib(const std::string& bytes);

// Box-filters an image whose sides are `factor` times larger.
RgbaImage downsample(const RgbaImage& image, uint32_t factor);

}  // namespace ink
