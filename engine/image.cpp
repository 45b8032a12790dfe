#include "image.h"

#include "common.h"
#include "files.h"

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

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

// Encoded in memory, then written with every write and the close checked (writeFileAtomically): stb's own
// file writer ignores write errors, so a full disk gave a truncated PNG and success.
void writePng(const std::string& path, const RgbaImage& image) {
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, int(image.width), int(image.height), 4, image.pixels.data(),
                                int(image.width * 4)))
        throw Error("cannot write '" + path + "': PNG encoding failed");
    writeFileAtomically(path, bytes);
}

RgbaImage readPng(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!data) throw Error("cannot read '" + path + "' as PNG: " + stbi_failure_reason());
    RgbaImage image{uint32_t(w), uint32_t(h), std::vector<uint8_t>(data, data + size_t(w) * size_t(h) * 4)};
    stbi_image_free(data);
    return image;
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
