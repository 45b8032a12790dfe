#include "base/image.h"

#include "base/common.h"
#include "base/files.h"

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb_image.h>
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace ink {

std::string deflateZlib(const std::string& bytes) {
    if (bytes.size() > size_t(std::numeric_limits<int>::max())) throw Error("deflate: more than 2 GiB of data");
    int size = 0;
    unsigned char* data = stbi_zlib_compress(reinterpret_cast<unsigned char*>(const_cast<char*>(bytes.data())),
                                             int(bytes.size()), &size, 8);
    if (!data) throw Error("deflate: out of memory");
    std::string out(reinterpret_cast<const char*>(data), size_t(size));
    STBIW_FREE(data);
    return out;
}

// Encoded in memory, then written with every write and the close checked (writeFileAtomically): stb's own
// file writer ignores write errors, so a full disk gave a truncated PNG and success.
void writePng(const std::string& path, const RgbaImage& image) {
    writePng(path, image.width, image.height, image.pixels.data());
}

void writePng(const std::string& path, uint32_t width, uint32_t height, const uint8_t* rgba) {
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, int(width), int(height), 4, rgba, int(width * 4)))
        throw Error("cannot write '" + path + "': PNG encoding failed");
    writeFileAtomically(path, bytes);
}

namespace {

// A file name or stb's reason for a message: bytes outside printable ASCII become '?' (a raw non-UTF-8
// byte made the message itself invalid text).
std::string printable(std::string_view s) {
    std::string out;
    for (unsigned char c : s) out += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
    return out;
}

// stb's reason for the last failure, printable; some failures leave it empty.
std::string reason() {
    const char* text = stbi_failure_reason();
    return text && *text ? printable(text) : "not a PNG, or a broken one";
}

}  // namespace

RgbaImage readPngFromMemory(const std::string& bytes, const std::string& name) {
    const std::string what = "cannot read '" + printable(name) + "' as PNG: ";
    if (bytes.size() > size_t(std::numeric_limits<int>::max())) throw Error(what + "the file is larger than 2 GiB");
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = int(bytes.size());
    // The header first: a few kilobytes of PNG may claim 8000x8000 pixels and make stb allocate hundreds of
    // megabytes (a decompression bomb). Refuse such sizes before anything is decoded.
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(data, size, &w, &h, &channels)) throw Error(what + reason());
    if (w < 1 || h < 1 || uint64_t(w) > kMaxImageSide || uint64_t(h) > kMaxImageSide ||
        uint64_t(w) * uint64_t(h) > kMaxImagePixels)
        throw Error(what + std::to_string(w) + "x" + std::to_string(h) + " pixels is over the limit (at most " +
                    std::to_string(kMaxImageSide) + " a side and " + std::to_string(kMaxImagePixels) +
                    " pixels = 8192^2 in all)");
    // Within those, a file far smaller than its pixels need: an 8-bit RGBA PNG decodes to at most 1032 bytes
    // per byte of data (deflate's largest ratio), so more than kMaxImageExpansion bytes of RGBA per byte of
    // file is a low-bit-depth bomb (a 7.8 KB 1-bit PNG of 8000x8000 pixels took 766 MB). Every PNG Inkwell
    // writes (8-bit RGBA) passes; small images always do.
    const uint64_t decoded = uint64_t(w) * uint64_t(h) * 4;
    if (uint64_t(w) * uint64_t(h) > kMinImageForRatio && decoded / kMaxImageExpansion > bytes.size())
        throw Error(what + std::to_string(w) + "x" + std::to_string(h) + " pixels (" + std::to_string(decoded >> 20) +
                    " MiB decoded) from " + std::to_string(bytes.size()) +
                    " bytes is a decompression bomb: more than " + std::to_string(kMaxImageExpansion) +
                    " bytes of pixels per byte of file");
    // The chunks, before stb sees them (both found by fuzz_png): stb grows its buffer to a chunk's declared
    // length before reading it, so a 100-byte file claiming a 2 GiB IDAT allocated 2 GiB; and it copies a
    // first IDAT chunk of length 0 with memcpy from a null pointer (undefined behaviour).
    bool seenData = false;
    for (size_t at = 8; at + 8 <= bytes.size();) {
        uint32_t length = 0;
        for (size_t k = 0; k < 4; ++k) length = (length << 8) | uint8_t(bytes[at + k]);
        std::string_view type(bytes.data() + at + 4, 4);
        if (uint64_t(length) + 12 > bytes.size() - at)
            throw Error(what + "truncated: chunk " + printable(type) + " claims " + std::to_string(length) +
                        " bytes, " + std::to_string(bytes.size() - at) + " are left");
        if (type == "IDAT") {
            if (length == 0 && !seenData) throw Error(what + "an empty IDAT chunk before the image data");
            seenData = true;
        }
        if (type == "IEND") break;
        at += size_t(length) + 12;
    }
    stbi_uc* pixels = stbi_load_from_memory(data, size, &w, &h, &channels, 4);
    if (!pixels) throw Error(what + reason());
    RgbaImage image{uint32_t(w), uint32_t(h), std::vector<uint8_t>(pixels, pixels + size_t(w) * size_t(h) * 4)};
    stbi_image_free(pixels);
    return image;
}

RgbaImage readPng(const std::string& path) {
    // A 2^26-pixel PNG compresses to far less than this; the cap only stops a wrong file being slurped.
    std::string bytes;
    try {
        bytes = readFileCapped(path, size_t(256) << 20, "file is larger than 256 MiB, too large for an image");
    } catch (const Error& e) {
        throw Error(printable(e.what()));
    }
    return readPngFromMemory(bytes, path);
}

RgbaImage downsample(const RgbaImage& image, uint32_t factor) {
    if (factor <= 1) return image;
    RgbaImage out{image.width / factor, image.height / factor, {}};
    out.pixels.resize(size_t(out.width) * out.height * 4);
    const uint32_t area = factor * factor;
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (uint32_t c = 0; c < 4; ++c) {
                uint32_t sum = 0;
                for (uint32_t dy = 0; dy < factor; ++dy)
                    for (uint32_t dx = 0; dx < factor; ++dx)
                        sum += image.pixels[(size_t(y * factor + dy) * image.width + (x * factor + dx)) * 4 + c];
                out.pixels[(size_t(y) * out.width + x) * 4 + c] = uint8_t((sum + area / 2) / area);
            }
    return out;
}

}  // namespace ink
