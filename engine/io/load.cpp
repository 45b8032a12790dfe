// The entry points of points.h: a file's format picked by its extension, read with the file size capped.
#include "base/common.h"
#include "io/points.h"
#include "io/readers.h"
#include "io/text.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace ink {
namespace {

const char* const kSupported = ".obj .ply .pts .xyzn .txt .xyz .pwn .off .stl .gltf .glb";

std::string readModelFile(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::file_status status = fs::status(path, ec);
    if (ec) throw Error("cannot open '" + path + "': " + ec.message());
    if (fs::is_directory(status)) throw Error("cannot open '" + path + "': " + std::strerror(EISDIR));
    if (fs::is_regular_file(status)) {
        uintmax_t size = fs::file_size(path, ec);
        if (!ec && size > io::kMaxFileBytes)
            io::fail(path, "file is " + std::to_string(size) + " bytes; the limit is 2 GiB");
    }
    return readFileCapped(path, io::kMaxFileBytes, "file is larger than the limit of 2 GiB");
}

}  // namespace

OrientedPoints loadPoints(const std::string& path) {
    std::string file = std::filesystem::path(path).filename().string();
    size_t dot = file.rfind('.');
    std::string ext = dot == std::string::npos ? "" : file.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    std::string format;
    if (ext == "obj")
        format = "obj";
    else if (ext == "ply")
        format = "ply";
    else if (ext == "pts" || ext == "xyzn" || ext == "txt")
        format = "pts";
    else if (ext == "xyz" || ext == "pwn")
        format = "xyz";
    else if (ext == "off" || ext == "stl" || ext == "gltf" || ext == "glb")
        format = ext;
    else
        io::fail(path, (ext.empty() ? std::string("no file extension") : "unsupported file extension '." + ext + "'") +
                           "; supported: " + kSupported);
    return parsePoints(readModelFile(path), format, path);
}

OrientedPoints parsePoints(const std::string& bytes, const std::string& format, const std::string& name) {
    if (format == "obj") return io::parseObj(bytes, name);
    if (format == "ply") return io::parsePly(bytes, name);
    if (format == "pts") return io::parsePts(bytes, name);
    if (format == "xyz") return io::parsePts(bytes, name, true);
    if (format == "off") return io::parseOff(bytes, name);
    if (format == "stl") return io::parseStl(bytes, name);
    // External buffers are looked for beside `name`, the file the bytes came from.
    if (format == "gltf" || format == "glb") return io::parseGltf(bytes, name, format == "glb", true);
    io::fail(name, "unknown point format '" + format + "' (expected obj, ply, pts, xyz, off, stl, gltf or glb)");
}

}  // namespace ink
