#include "image.h"

#include "common.h"

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

namespace {

std::string temporaryPath(const std::string& path) { return path + ".tmp" + std::to_string(getpid()); }

}  // namespace

void checkWritable(const std::string& path) {
    if (path.empty()) return;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error("cannot write '" + path + "': " + std::strerror(EISDIR));
    std::string tmp = temporaryPath(path);
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (!file) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    std::fclose(file);
    std::remove(tmp.c_str());
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    std::string tmp = temporaryPath(path);
    try {
        write(tmp);
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int e = errno;
        std::remove(tmp.c_str());
        throw Error("cannot write '" + path + "': " + std::strerror(e));
    }
}

void writePng(const std::string& path, const RgbaImage& image) {
    writeAtomically(path, [&](const std::string& tmp) {
        errno = 0;
        if (!stbi_write_png(tmp.c_str(), int(image.width), int(image.height), 4, image.pixels.data(),
                            int(image.width * 4)))
            throw Error("cannot write '" + path + "': " + (errno ? std::strerror(errno) : "PNG encoding failed"));
    });
}

RgbaImage readPng(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!data) throw Error("cannot read '" + path + "' as PNG: " + stbi_failure_reason());
    RgbaImage image{uint32_t(w), uint32_t(h), std::vector<uint8_t>(data, data + size_t(w) * size_t(h) * 4)};
    stbi_image_free(data);
    return image;
}

}  // namespace ink
