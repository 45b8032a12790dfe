#include "io/export.h"

#include "base/common.h"
#include "base/files.h"

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>

namespace ink {

namespace {

// The positions in the input's units, and whether float32 holds them: to 1e-6 of the diagonal, finite. A
// unit sphere at (1e7, 1e7, 1e7) does not fit (float32 keeps 7 digits: 26 distinct positions), nor does a
// 1e300 sphere (infinities) or a 1e-300 one (all zero); those are written as float64.
bool floatHolds(const std::vector<Eigen::Vector3d>& positions, const Frame& frame) {
    const double tolerance = 1e-6 / frame.scale;
    for (const Eigen::Vector3d& x : positions)
        for (int k = 0; k < 3; ++k) {
            // Beyond float's range the conversion itself is undefined: test before converting.
            if (!(std::abs(x[k]) <= double(std::numeric_limits<float>::max()))) return false;
            if (!(std::abs(double(float(x[k])) - x[k]) <= tolerance)) return false;
        }
    return true;
}

template <typename T>
void append(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

}  // namespace

void writePointsPly(const std::string& path, const std::vector<PointRecord>& points, const Frame& frame) {
    std::vector<Eigen::Vector3d> positions(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const PointRecord& p = points[i];
        positions[i] = frame.toInput(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
    }
    const bool single = floatHolds(positions, frame);
    const char* type = single ? "float" : "double";
    std::string bytes = std::string("ply\nformat binary_little_endian 1.0\ncomment inkwell refined points\n") +
                        "element vertex " + std::to_string(points.size()) + "\n" + "property " + type +
                        " x\nproperty " + type + " y\nproperty " + type + " z\n" +
                        "property float nx\nproperty float ny\nproperty float nz\n" +
                        "property int level\nproperty float rank\nend_header\n";
    static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");
    bytes.reserve(bytes.size() + points.size() * (single ? 32 : 44));
    for (size_t i = 0; i < points.size(); ++i) {
        const PointRecord& p = points[i];
        for (int k = 0; k < 3; ++k) {
            if (single)
                append(bytes, float(positions[i][k]));
            else
                append(bytes, positions[i][k]);
        }
        for (int k = 0; k < 3; ++k) append(bytes, p.normal[k]);
        append(bytes, int32_t(p.level));
        append(bytes, p.tone);
    }
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    });
}

}  // namespace ink
