#include "points.h"

#include "common.h"

#include <tiny_obj_loader.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <istream>
#include <limits>
#include <string_view>
#include <system_error>
#include <tuple>

namespace ink {
namespace {

// Header counts above this are refused outright, whatever the file size: no real input is that big, and
// it keeps a hostile header from turning into a huge allocation or loop.
constexpr uint64_t kMaxElements = 100'000'000;
constexpr uint64_t kMaxFileBytes = uint64_t(2) << 30;  // 2 GiB
// Normals read from a file (already meant to be unit length) shorter than this count as zero.
constexpr double kZeroNormal = 1e-12;

using Eigen::Vector3d;

[[noreturn]] void fail(const std::string& name, const std::string& what) { throw Error(name + ": " + what); }

std::string str(const Vector3d& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", v.x(), v.y(), v.z());
    return buf;
}

// A number read from a file, for messages; it may be huge or negative when the file is corrupt.
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.15g", v);
    return buf;
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Splits on blanks; `out` is reused across calls to avoid reallocating per line.
void splitFields(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        size_t start = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
}

// Locale-independent, whole-token number parsing (strtod would accept "1.5abc" prefixes and obey the
// locale's decimal point). "nan" and "inf" parse; the finiteness checks reject them with a location.
bool toDouble(std::string_view s, double& out) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    if (end != s.data() + s.size() || s.empty()) return false;
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports both overflow and underflow this way; strtod tells them apart (+-HUGE_VAL
        // or a tiny value), and the token is known to be a well-formed number by now.
        out = std::strtod(std::string(s).c_str(), nullptr);
        return true;
    }
    return ec == std::errc();
}

bool toInt(std::string_view s, int64_t& out) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && !s.empty() && end == s.data() + s.size();
}

// Text lines ending in "\n", "\r\n" or "\r" (the same rule tinyobjloader uses, so line numbers agree).
class Lines {
public:
    explicit Lines(std::string_view text, size_t start = 0, size_t firstNumber = 1)
        : text_(text), pos_(start), number_(firstNumber - 1) {}

    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        size_t end = std::min(text_.find_first_of("\r\n", pos_), text_.size());
        line = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
        if (end < text_.size() && text_[end] == '\r' && pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
        ++number_;
        return true;
    }
    size_t number() const { return number_; }
    size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }

private:
    std::string_view text_;
    size_t pos_;
    size_t number_;
};

// Text formats never contain NUL; finding one means the file is binary, and saying so is clearer than
// whatever parse error the garbage would cause next. `firstLine` is the number of the text's first line.
void rejectBinary(std::string_view text, const std::string& name, size_t firstLine = 1) {
    size_t nul = text.find('\0');
    if (nul == std::string_view::npos) return;
    Lines lines(text.substr(0, nul + 1), 0, firstLine);
    for (std::string_view line; lines.next(line);) {}
    fail(name, "line " + std::to_string(lines.number()) + ": binary data (a NUL byte) in a text file");
}

// Polygons as a flat index list plus sizes (any size >= 3).
struct Polygons {
    std::vector<uint32_t> indices;
    std::vector<uint32_t> sizes;
};

// Adds each polygon's area vector to its vertices. For a fan-triangulated polygon the sum of the fan's
// edge cross products is twice its area times its normal, so big faces weigh more than slivers, and
// non-convex polygons still come out right.
void addAreaNormals(const std::vector<Vector3d>& positions, const Polygons& polygons, std::vector<Vector3d>& sums,
                    std::vector<char>& used) {
    size_t offset = 0;
    for (uint32_t size : polygons.sizes) {
        const uint32_t* idx = polygons.indices.data() + offset;
        offset += size;
        const Vector3d& p0 = positions[idx[0]];
        Vector3d area = Vector3d::Zero();
        for (uint32_t k = 1; k + 1 < size; ++k) area += (positions[idx[k]] - p0).cross(positions[idx[k + 1]] - p0);
        for (uint32_t k = 0; k < size; ++k) {
            sums[idx[k]] += area;
            used[idx[k]] = 1;
        }
    }
}

// Length of v without overflow or underflow in the squares.
double safeNorm(const Vector3d& v) {
    double big = v.cwiseAbs().maxCoeff();
    return big > 0 && std::isfinite(big) ? big * (v / big).norm() : big;
}

// The bounding-box diagonal of the vertices faces use: the scale against which area normals are judged.
double usedDiagonal(const std::vector<Vector3d>& positions, const std::vector<char>& used) {
    Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (size_t i = 0; i < positions.size(); ++i) {
        if (!used[i]) continue;
        lo = lo.cwiseMin(positions[i]);
        hi = hi.cwiseMax(positions[i]);
    }
    return safeNorm(hi - lo);
}

// Area sums scale with the model's size squared, so "zero" means tiny next to the squared diagonal (the
// division order avoids overflowing the square). The sum is then brought to unit length so that finish()
// can treat it like a normal read from a file.
template <class Where>
void settleAreaNormal(Vector3d& n, double diagonal, const std::string& name, Where where) {
    double length = safeNorm(n);
    if (!std::isfinite(length)) return;  // finish() reports it
    if (length == 0 || (std::isfinite(diagonal) && length / diagonal / diagonal <= 1e-12))
        fail(name, where() + ": normal is zero (the faces around it have no area)");
    n /= length;
}

// Checks and normalizes; `where(i)` names point i for messages ("vertex 17", "line 4").
template <class Where>
void finish(OrientedPoints& points, const std::string& name, Where where) {
    if (points.positions.empty()) fail(name, "no vertices");
    for (size_t i = 0; i < points.positions.size(); ++i) {
        const Vector3d& p = points.positions[i];
        Vector3d& n = points.normals[i];
        if (!p.allFinite()) fail(name, where(i) + ": coordinate is not finite " + str(p));
        if (!n.allFinite()) fail(name, where(i) + ": normal is not finite " + str(n));
        double length = safeNorm(n);
        if (!(length > kZeroNormal)) fail(name, where(i) + ": normal is zero");
        n /= length;
    }
}

// ----------------------------------------------------------------------------------------------------
// OBJ

// tinyobjloader reads from an istream; this one reads bytes in place instead of copying them.
struct MemoryBuffer : std::streambuf {
    MemoryBuffer(const char* begin, size_t size) {
        char* p = const_cast<char*>(begin);  // never written: the get area only
        setg(p, p, p + size);
    }
};

// What our own pass over the file collects. tinyobjloader is lenient (non-numbers become 0, out of range
// indices are warnings) and the packaged build stores floats, so coordinates are read here, in double,
// with line numbers; tinyobjloader supplies the face structure.
struct ObjScan {
    std::vector<Vector3d> v, vn;
    std::vector<size_t> vLine, vnLine;
    size_t faces = 0;
    // What tinyobjloader gets to read: the v, vn and f lines this pass checked, rebuilt from their fields
    // ("v x y z", "f 1//2 3//4 5//6"), and an empty line for every other line, so line numbers stay the
    // same. tinyobjloader never sees the lines it parses but we ignore (vt, vw, t, l, p, g, ...): fuzzing
    // found undefined behaviour in its `vw` parser (a float out of int range), and what it does with them
    // is of no use to us anyway.
    std::string checked;
};

std::string lineName(size_t line) { return "line " + std::to_string(line); }

// Splits a face corner "v", "v/vt", "v/vt/vn" or "v//vn" into its indices (0 where absent), refusing
// anything else; tinyobjloader would read a malformed corner as index 0 or as whatever atoi makes of it.
bool splitCorner(std::string_view corner, int64_t index[3], size_t& count) {
    count = 0;
    size_t start = 0;
    for (;;) {
        if (count == 3) return false;
        size_t slash = corner.find('/', start);
        std::string_view part = corner.substr(start, slash == std::string_view::npos ? slash : slash - start);
        index[count] = 0;
        bool optional = count == 1;  // the vt of v//vn
        if (part.empty() ? !optional : !toInt(part, index[count]) || index[count] == 0) return false;
        ++count;
        if (slash == std::string_view::npos) break;
        start = slash + 1;
    }
    return !(count == 2 && index[1] == 0);  // "v/"
}

ObjScan scanObj(const std::string& bytes, const std::string& name) {
    rejectBinary(bytes, name);
    ObjScan scan;
    // Positive indices may point forward (tinyobjloader resolves them after reading everything), so they
    // are checked at the end; only those beyond the count so far need remembering.
    struct Pending {
        size_t line;
        int64_t index;
        bool normal;
    };
    std::vector<Pending> pending;
    std::vector<std::string_view> fields;
    Lines lines(bytes);
    std::string_view line;
    while (lines.next(line)) {
        size_t at = line.find_first_not_of(" \t");
        if (at == std::string_view::npos) continue;
        line.remove_prefix(at);
        auto where = [&] { return lineName(lines.number()); };
        auto space = [&](size_t i) { return line.size() > i && (line[i] == ' ' || line[i] == '\t'); };
        bool vertex = line[0] == 'v' && space(1);
        bool normal = line[0] == 'v' && line.size() > 1 && line[1] == 'n' && space(2);
        bool face = line[0] == 'f' && space(1);
        if (!vertex && !normal && !face) {
            scan.checked += '\n';
            continue;
        }
        splitFields(line.substr(vertex || face ? 2 : 3), fields);
        auto keep = [&] {
            scan.checked += vertex ? "v" : normal ? "vn" : "f";
            for (std::string_view field : fields) (scan.checked += ' ') += field;
            scan.checked += '\n';
        };

        if (vertex || normal) {
            // A trailing comment is allowed (and not passed on to tinyobjloader).
            auto comment = std::find_if(fields.begin(), fields.end(), [](auto f) { return f[0] == '#'; });
            fields.erase(comment, fields.end());
            // v takes x y z, optionally w or r g b (which we ignore); vn exactly x y z.
            size_t most = vertex ? 7 : 3;
            if (fields.size() < 3 || fields.size() > most)
                fail(name, where() + ": expected " + (vertex ? "3 to 7" : "3") + " numbers after '" +
                               (vertex ? "v" : "vn") + "', found " + std::to_string(fields.size()));
            Vector3d p;
            for (size_t k = 0; k < fields.size(); ++k) {
                double value;
                if (!toDouble(fields[k], value)) fail(name, where() + ": " + quoted(fields[k]) + " is not a number");
                if (k < 3) p[Eigen::Index(k)] = value;
            }
            if (!p.allFinite())
                fail(name, where() + ": " + (vertex ? "coordinate" : "normal") + " is not finite " + str(p));
            (vertex ? scan.v : scan.vn).push_back(p);
            (vertex ? scan.vLine : scan.vnLine).push_back(lines.number());
            if (scan.v.size() > kMaxElements || scan.vn.size() > kMaxElements)
                fail(name, where() + ": more than " + std::to_string(kMaxElements) + " vertices or normals");
            keep();
            continue;
        }

        if (fields.size() < 3)
            fail(name, where() + ": face has " + std::to_string(fields.size()) + " vertices; at least 3 are needed");
        // tinyobjloader keeps polygon sizes in an unsigned char.
        if (fields.size() > 255)
            fail(name,
                 where() + ": face has " + std::to_string(fields.size()) + " vertices; at most 255 are supported");
        for (std::string_view corner : fields) {
            int64_t index[3];
            size_t count;
            if (!splitCorner(corner, index, count))
                fail(name, where() + ": " + quoted(corner) +
                               " is not a face vertex (v, v/vt, v/vt/vn or v//vn; indices are nonzero integers)");
            for (int slot : {0, 2}) {
                if (slot == 2 && count < 3) break;
                bool isNormal = slot == 2;
                int64_t i = index[slot];
                int64_t have = int64_t(isNormal ? scan.vn.size() : scan.v.size());
                const char* what = isNormal ? "normal" : "vertex";
                if (i < 0 && i + have < 0)
                    fail(name, where() + ": face " + what + " index " + std::to_string(i) +
                                   " reaches before the first " + what + " (only " + std::to_string(have) + " so far)");
                if (i > have) pending.push_back({lines.number(), i, isNormal});
            }
            // The texture coordinate index is not used, but tinyobjloader reads it into an int.
            constexpr int64_t kMaxInt = std::numeric_limits<int>::max();
            if (count >= 2 && (index[1] > kMaxInt || index[1] < -kMaxInt))
                fail(name,
                     where() + ": face texture coordinate index " + std::to_string(index[1]) + " is out of range");
        }
        keep();
        ++scan.faces;
    }
    for (const Pending& p : pending) {
        size_t have = p.normal ? scan.vn.size() : scan.v.size();
        if (uint64_t(p.index) > have)
            fail(name, lineName(p.line) + ": face " + (p.normal ? "normal" : "vertex") + " index " +
                           std::to_string(p.index) + " is out of range (the file has " + std::to_string(have) + " " +
                           (p.normal ? "normals" : "vertices") + ")");
    }
    return scan;
}

// tinyobjloader messages come several to a string, each ending in a newline; a user gets one line.
std::string oneLine(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

OrientedPoints parseObj(const std::string& bytes, const std::string& name) {
    ObjScan scan = scanObj(bytes, name);
    if (scan.v.empty()) fail(name, "no vertices");

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    MemoryBuffer buffer(scan.checked.data(), scan.checked.size());
    std::istream in(&buffer);
    // No material reader, and no mtllib lines reach it anyway: no files next to who knows what are opened.
    // No triangulation: its ear clipping silently drops triangles it cannot place, and we only need
    // polygon area vectors anyway. Warnings (missing materials and the like) are not our concern; every
    // index problem was already refused by scanObj.
    bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, nullptr, false, false);
    if (!ok) fail(name, "tinyobjloader: " + oneLine(err));
    if (attrib.vertices.size() != 3 * scan.v.size() || attrib.normals.size() != 3 * scan.vn.size())
        fail(name, "tinyobjloader and our own reading disagree on the number of vertices or normals");

    Polygons polygons;
    std::vector<int> cornerNormals;  // vn index per corner, -1 where the corner has none
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& mesh = shape.mesh;
        size_t offset = 0;
        for (unsigned char size : mesh.num_face_vertices) {
            if (offset + size > mesh.indices.size()) fail(name, "tinyobjloader returned inconsistent faces");
            for (size_t k = offset; k < offset + size; ++k) {
                const tinyobj::index_t& c = mesh.indices[k];
                if (c.vertex_index < 0 || size_t(c.vertex_index) >= scan.v.size() || c.normal_index < -1 ||
                    c.normal_index >= int(scan.vn.size()))
                    fail(name, "tinyobjloader returned a face index out of range");
                polygons.indices.push_back(uint32_t(c.vertex_index));
                cornerNormals.push_back(c.normal_index);
            }
            polygons.sizes.push_back(size);
            offset += size;
        }
    }
    if (polygons.sizes.size() != scan.faces)
        fail(name, "tinyobjloader and our own reading disagree on the number of faces");

    OrientedPoints out;
    if (polygons.sizes.empty()) {
        // A point cloud written as OBJ: normals can only pair with vertices one to one, in order.
        if (scan.vn.empty()) fail(name, "has no faces and no normals: cannot orient points");
        if (scan.vn.size() != scan.v.size())
            fail(name, "has no faces, and its " + std::to_string(scan.vn.size()) + " normals do not pair up with its " +
                           std::to_string(scan.v.size()) + " vertices");
        out.positions = scan.v;
        out.normals = scan.vn;
        finish(out, name,
               [&](size_t i) { return "vertex " + std::to_string(i + 1) + " (" + lineName(scan.vLine[i]) + ")"; });
        return out;
    }

    size_t n = scan.v.size();
    std::vector<Vector3d> area(n, Vector3d::Zero()), given(n, Vector3d::Zero());
    std::vector<char> used(n, 0), hasGiven(n, 0);
    addAreaNormals(scan.v, polygons, area, used);
    // Normals named by faces win over computed ones; a vertex met with several is given their average.
    for (size_t k = 0; k < cornerNormals.size(); ++k) {
        int ni = cornerNormals[k];
        if (ni < 0) continue;
        const Vector3d& vn = scan.vn[size_t(ni)];
        double length = safeNorm(vn);
        if (!(length > kZeroNormal)) fail(name, lineName(scan.vnLine[size_t(ni)]) + ": normal is zero");
        uint32_t vi = polygons.indices[k];
        given[vi] += vn / length;
        hasGiven[vi] = 1;
    }

    std::vector<size_t> vertexOf;
    double diagonal = usedDiagonal(scan.v, used);
    for (size_t i = 0; i < n; ++i) {
        if (!used[i]) continue;
        auto where = [&] { return "vertex " + std::to_string(i + 1) + " (" + lineName(scan.vLine[i]) + ")"; };
        if (!hasGiven[i]) settleAreaNormal(area[i], diagonal, name, where);
        vertexOf.push_back(i);
        out.positions.push_back(scan.v[i]);
        out.normals.push_back(hasGiven[i] ? given[i] : area[i]);
    }
    // Several given normals can still cancel out; finish() calls that a zero normal too.
    finish(out, name, [&](size_t i) {
        return "vertex " + std::to_string(vertexOf[i] + 1) + " (" + lineName(scan.vLine[vertexOf[i]]) + ")";
    });
    return out;
}

// ----------------------------------------------------------------------------------------------------
// PLY

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool plyType(std::string_view s, PlyType& t) {
    static const std::pair<std::string_view, PlyType> kTypes[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& [word, type] : kTypes)
        if (word == s) {
            t = type;
            return true;
        }
    return false;
}

size_t sizeOf(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 8;
}

bool isInteger(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
    std::string name;
    bool list = false;
    PlyType countType = PlyType::UInt8;
    PlyType type = PlyType::Float32;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;

    // The fewest bytes one entry can take: every scalar at full size, every list empty.
    uint64_t minBinarySize() const {
        uint64_t size = 0;
        for (const PlyProperty& p : properties) size += sizeOf(p.list ? p.countType : p.type);
        return size;
    }
    int find(std::string_view property) const {
        for (size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == property) return int(i);
        return -1;
    }
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t bodyStart = 0;
    size_t bodyFirstLine = 0;  // for ascii messages
};

PlyHeader parsePlyHeader(const std::string& bytes, const std::string& name) {
    PlyHeader header;
    size_t pos = 0, number = 0;
    // The header is always "\n" (or "\r\n") separated text, and a binary body starts right after the
    // end_header line, so lines are cut here by hand rather than with Lines.
    auto next = [&](std::string_view& line) {
        if (pos >= bytes.size()) return false;
        size_t end = bytes.find('\n', pos);
        size_t stop = end == std::string::npos ? bytes.size() : end;
        line = std::string_view(bytes).substr(pos, stop - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = stop == bytes.size() ? stop : stop + 1;
        ++number;
        return true;
    };
    std::string_view line;
    if (!next(line) || line != "ply") fail(name, "not a PLY file (the first line is not 'ply')");

    bool haveFormat = false;
    std::vector<std::string_view> f;
    while (next(line)) {
        auto where = [&] { return "header line " + std::to_string(number); };
        splitFields(line, f);
        if (f.empty() || f[0] == "comment" || f[0] == "obj_info") continue;
        if (f[0] == "end_header") {
            if (!haveFormat) fail(name, "header has no format line");
            header.bodyStart = pos;
            header.bodyFirstLine = number + 1;
            return header;
        }
        if (f[0] == "format") {
            double version = 0;
            bool ok = f.size() == 3 && toDouble(f[2], version) && version == 1.0;
            if (ok && f[1] == "ascii")
                header.format = PlyFormat::Ascii;
            else if (ok && f[1] == "binary_little_endian")
                header.format = PlyFormat::BinaryLittleEndian;
            else if (ok && f[1] == "binary_big_endian")
                header.format = PlyFormat::BinaryBigEndian;
            else
                fail(name, where() + ": bad format line " + quoted(line) +
                               " (expected 'format ascii|binary_little_endian|binary_big_endian 1.0')");
            if (haveFormat) fail(name, where() + ": a second format line");
            haveFormat = true;
        } else if (f[0] == "element") {
            uint64_t count = 0;
            bool ok = f.size() == 3;
            if (ok) {
                auto [end, ec] = std::from_chars(f[2].data(), f[2].data() + f[2].size(), count);
                ok = ec == std::errc() && end == f[2].data() + f[2].size();
            }
            if (!ok) fail(name, where() + ": bad element line " + quoted(line) + " (expected 'element NAME COUNT')");
            if (count > kMaxElements)
                fail(name, where() + ": element '" + std::string(f[1]) + "' claims " + std::to_string(count) +
                               " entries; the limit is " + std::to_string(kMaxElements));
            for (const PlyElement& e : header.elements)
                if (e.name == f[1]) fail(name, where() + ": a second element '" + e.name + "'");
            header.elements.push_back({std::string(f[1]), count, {}});
        } else if (f[0] == "property") {
            if (header.elements.empty()) fail(name, where() + ": property before any element");
            PlyProperty p;
            bool ok;
            if (f.size() >= 2 && f[1] == "list") {
                ok = f.size() == 5 && plyType(f[2], p.countType) && isInteger(p.countType) && plyType(f[3], p.type);
                p.list = true;
            } else {
                ok = f.size() == 3 && plyType(f[1], p.type);
            }
            if (!ok)
                fail(name, where() + ": bad property line " + quoted(line) +
                               " (expected 'property TYPE NAME' or 'property list INTTYPE TYPE NAME')");
            p.name = std::string(f.back());
            PlyElement& e = header.elements.back();
            if (e.find(p.name) >= 0) fail(name, where() + ": a second property '" + p.name + "' in '" + e.name + "'");
            e.properties.push_back(std::move(p));
        } else {
            fail(name, where() + ": unknown header keyword " + quoted(f[0]));
        }
    }
    fail(name, "header has no end_header line");
}

// Reads the body value by value in either encoding, so one loop serves ascii and both binaries. Knows
// which entry it is in, for messages.
class PlyBody {
public:
    PlyBody(const std::string& bytes, const PlyHeader& header, const std::string& name)
        : bytes_(bytes),
          name_(name),
          format_(header.format),
          pos_(header.bodyStart),
          lines_(bytes, header.bodyStart, header.bodyFirstLine) {}

    // Refuses an element the rest of the file cannot possibly hold before anything is allocated for it.
    void beginElement(const PlyElement& e) {
        element_ = &e;
        entry_ = 0;
        if (format_ == PlyFormat::Ascii) {
            // Each value needs at least one character.
            if (e.count * e.properties.size() > lines_.remaining())
                fail(name_, "truncated: the header declares " + std::to_string(e.count) + " " + plural() +
                                " but only " + std::to_string(lines_.remaining()) + " bytes are left");
            return;
        }
        uint64_t size = e.minBinarySize(), left = bytes_.size() - pos_;
        if (size == 0 || e.count * size <= left) return;
        bool fixed = std::none_of(e.properties.begin(), e.properties.end(), [](auto& p) { return p.list; });
        if (fixed) {
            entry_ = left / size;
            truncated();
        }
        fail(name_, "truncated: the header declares " + std::to_string(e.count) + " " + plural() + " of at least " +
                        std::to_string(size) + " bytes, but only " + std::to_string(left) + " bytes are left");
    }

    void beginEntry(uint64_t entry) {
        entry_ = entry;
        field_ = 0;
        fields_.clear();
        if (format_ != PlyFormat::Ascii || element_->properties.empty()) return;
        std::string_view line;
        do {
            if (!lines_.next(line)) truncated();
            rejectBinary(line, name_, lines_.number());
            splitFields(line, fields_);
        } while (fields_.empty());
    }

    void endEntry() {
        if (format_ == PlyFormat::Ascii && field_ != fields_.size())
            fail(name_,
                 where() + ": " + std::to_string(fields_.size() - field_) + " more values than the header declares");
    }

    double scalar(PlyType t) {
        if (format_ == PlyFormat::Ascii) {
            if (field_ == fields_.size()) fail(name_, where() + ": fewer values than the header declares");
            std::string_view s = fields_[field_++];
            double v;
            if (!toDouble(s, v)) fail(name_, where() + ": " + quoted(s) + " is not a number");
            if (isInteger(t) && v != std::floor(v)) fail(name_, where() + ": " + quoted(s) + " is not an integer");
            return v;
        }
        size_t n = sizeOf(t);
        if (bytes_.size() - pos_ < n) truncated();
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + pos_, n);
        pos_ += n;
        bool big = format_ == PlyFormat::BinaryBigEndian;
        if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
        auto get = [&b](auto v) {
            std::memcpy(&v, b, sizeof v);
            return double(v);
        };
        switch (t) {
            case PlyType::Int8:
                return get(int8_t());
            case PlyType::UInt8:
                return get(uint8_t());
            case PlyType::Int16:
                return get(int16_t());
            case PlyType::UInt16:
                return get(uint16_t());
            case PlyType::Int32:
                return get(int32_t());
            case PlyType::UInt32:
                return get(uint32_t());
            case PlyType::Float32:
                return get(float());
            case PlyType::Float64:
                return get(double());
        }
        return 0;
    }

    // A list's length, checked against what is left so a corrupt count fails fast instead of looping.
    uint64_t listCount(const PlyProperty& p) {
        double v = scalar(p.countType);
        if (v < 0) fail(name_, where() + ": negative list length " + num(v));
        uint64_t left = format_ == PlyFormat::Ascii ? fields_.size() - field_ : (bytes_.size() - pos_) / sizeOf(p.type);
        if (v > double(left)) {
            if (format_ == PlyFormat::Ascii)
                fail(name_, where() + ": list '" + p.name + "' claims " + num(v) + " items but the line has " +
                                std::to_string(left) + " more values");
            truncated();
        }
        return uint64_t(v);
    }

    void skip(const PlyProperty& p) {
        if (!p.list) {
            scalar(p.type);
            return;
        }
        uint64_t count = listCount(p);
        if (format_ == PlyFormat::Ascii) {
            for (uint64_t k = 0; k < count; ++k) scalar(p.type);  // still checks they are numbers
        } else {
            pos_ += count * sizeOf(p.type);  // listCount checked it fits
        }
    }

    // Whatever data follows the last element is ignored, as other PLY readers do.

    std::string where() const {
        std::string entry = element_->name + " " + std::to_string(entry_);
        if (format_ != PlyFormat::Ascii) return entry;
        return "line " + std::to_string(lines_.number()) + " (" + entry + ")";
    }

    [[noreturn]] void truncated() const {
        fail(name_, "truncated: expected " + std::to_string(element_->count) + " " + plural() + ", file ends in " +
                        element_->name + " " + std::to_string(entry_));
    }

private:
    std::string plural() const { return element_->name == "vertex" ? "vertices" : "'" + element_->name + "' entries"; }

    const std::string& bytes_;
    const std::string& name_;
    PlyFormat format_;
    size_t pos_;   // binary
    Lines lines_;  // ascii
    std::vector<std::string_view> fields_;
    size_t field_ = 0;
    const PlyElement* element_ = nullptr;
    uint64_t entry_ = 0;
};

OrientedPoints parsePly(const std::string& bytes, const std::string& name) {
    PlyHeader header = parsePlyHeader(bytes, name);

    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name == "face") face = &e;
    }
    if (!vertex) fail(name, "has no 'element vertex' in its header");
    if (vertex->count == 0) fail(name, "no vertices");
    // Slot k of the vertex holds x y z nx ny nz; -1 where absent.
    static const char* const kSlots[6] = {"x", "y", "z", "nx", "ny", "nz"};
    int slot[6];
    for (int k = 0; k < 6; ++k) {
        slot[k] = vertex->find(kSlots[k]);
        if (slot[k] >= 0 && vertex->properties[size_t(slot[k])].list)
            fail(name, std::string("vertex property '") + kSlots[k] + "' is a list; it must be a number");
    }
    if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) fail(name, "vertex element lacks x, y or z");
    int normalSlots = (slot[3] >= 0) + (slot[4] >= 0) + (slot[5] >= 0);
    if (normalSlots != 0 && normalSlots != 3) fail(name, "vertex element has some of nx, ny, nz but not all three");
    bool hasNormals = normalSlots == 3;
    int faceList = -1;
    if (face) {
        faceList = face->find("vertex_indices");
        if (faceList < 0) faceList = face->find("vertex_index");
        if (faceList < 0 || !face->properties[size_t(faceList)].list)
            fail(name, "face element has no 'vertex_indices' list");
        if (!isInteger(face->properties[size_t(faceList)].type)) fail(name, "face vertex indices must be integers");
    }
    if (!hasNormals && (!face || face->count == 0))
        fail(name, "has no normals (nx ny nz) and no faces: cannot orient points");

    OrientedPoints points;
    Polygons polygons;
    PlyBody body(bytes, header, name);
    for (const PlyElement& e : header.elements) {
        body.beginElement(e);
        // An element without properties has nothing to read, in either encoding (an ascii entry would be
        // an empty line, and blank lines are skipped): skip it rather than count to a hostile 100 million,
        // fifty times over in a header of one kilobyte.
        if (e.properties.empty()) continue;
        if (&e == vertex) {
            points.positions.assign(e.count, Vector3d::Zero());
            points.normals.assign(e.count, Vector3d::Zero());
        }
        for (uint64_t i = 0; i < e.count; ++i) {
            body.beginEntry(i);
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& p = e.properties[k];
                if (&e == vertex && !p.list) {
                    double value = body.scalar(p.type);
                    for (int s = 0; s < 6; ++s)
                        if (slot[s] == int(k)) (s < 3 ? points.positions : points.normals)[i][s % 3] = value;
                } else if (&e == face && int(k) == faceList) {
                    uint64_t count = body.listCount(p);
                    if (count < 3)
                        fail(name,
                             body.where() + ": has " + std::to_string(count) + " vertices; at least 3 are needed");
                    for (uint64_t c = 0; c < count; ++c) {
                        double index = body.scalar(p.type);
                        if (index < 0 || index >= double(vertex->count))
                            fail(name, body.where() + ": vertex index " + num(index) +
                                           " is out of range (the file has " + std::to_string(vertex->count) +
                                           " vertices)");
                        polygons.indices.push_back(uint32_t(index));
                    }
                    polygons.sizes.push_back(uint32_t(count));
                } else {
                    body.skip(p);
                }
            }
            body.endEntry();
        }
    }

    auto where = [](size_t i) { return "vertex " + std::to_string(i); };
    if (hasNormals) {
        finish(points, name, where);
        return points;
    }
    // Vertices no face uses have no normal and are dropped, keeping their original numbers for messages.
    std::vector<Vector3d> sums(points.positions.size(), Vector3d::Zero());
    std::vector<char> used(points.positions.size(), 0);
    for (size_t i = 0; i < points.positions.size(); ++i)
        if (!points.positions[i].allFinite())
            fail(name, where(i) + ": coordinate is not finite " + str(points.positions[i]));
    addAreaNormals(points.positions, polygons, sums, used);
    double diagonal = usedDiagonal(points.positions, used);
    OrientedPoints out;
    std::vector<size_t> vertexOf;
    for (size_t i = 0; i < sums.size(); ++i) {
        if (!used[i]) continue;
        settleAreaNormal(sums[i], diagonal, name, [&] { return where(i); });
        vertexOf.push_back(i);
        out.positions.push_back(points.positions[i]);
        out.normals.push_back(sums[i]);
    }
    finish(out, name, [&](size_t i) { return where(vertexOf[i]); });
    return out;
}

// ----------------------------------------------------------------------------------------------------
// Oriented point text

OrientedPoints parsePts(const std::string& bytes, const std::string& name) {
    rejectBinary(bytes, name);
    OrientedPoints points;
    std::vector<size_t> lineOf;
    std::vector<std::string_view> fields;
    Lines lines(bytes);
    std::string_view line;
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        splitFields(line, fields);
        if (fields.empty()) continue;
        std::string where = lineName(lines.number());
        if (fields.size() != 6)
            fail(name,
                 where + ": expected 6 numbers (x y z nx ny nz), found " + std::to_string(fields.size()) + " fields");
        double v[6];
        for (size_t k = 0; k < 6; ++k)
            if (!toDouble(fields[k], v[k])) fail(name, where + ": " + quoted(fields[k]) + " is not a number");
        if (points.positions.size() >= kMaxElements)
            fail(name, where + ": more than " + std::to_string(kMaxElements) + " points");
        points.positions.emplace_back(v[0], v[1], v[2]);
        points.normals.emplace_back(v[3], v[4], v[5]);
        lineOf.push_back(lines.number());
    }
    finish(points, name, [&](size_t i) { return lineName(lineOf[i]); });
    return points;
}

std::string readFile(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::file_status status = fs::status(path, ec);
    if (ec) throw Error("cannot open '" + path + "': " + ec.message());
    if (fs::is_directory(status)) throw Error("cannot open '" + path + "': " + std::strerror(EISDIR));
    if (fs::is_regular_file(status)) {
        uintmax_t size = fs::file_size(path, ec);
        if (!ec && size > kMaxFileBytes) fail(path, "file is " + std::to_string(size) + " bytes; the limit is 2 GiB");
    }
    return readFileCapped(path, kMaxFileBytes, "file is larger than the limit of 2 GiB");
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
    else
        fail(path, (ext.empty() ? std::string("no file extension") : "unsupported file extension '." + ext + "'") +
                       "; supported: .obj .ply .pts .xyzn .txt");
    return parsePoints(readFile(path), format, path);
}

OrientedPoints parsePoints(const std::string& bytes, const std::string& format, const std::string& name) {
    if (format == "obj") return parseObj(bytes, name);
    if (format == "ply") return parsePly(bytes, name);
    if (format == "pts") return parsePts(bytes, name);
    fail(name, "unknown point format '" + format + "' (expected obj, ply or pts)");
}

size_t mergeDuplicates(OrientedPoints& points, double tolerance) {
    std::vector<Vector3d>& pos = points.positions;
    bool moveNormals = points.normals.size() == pos.size();
    bool exact = !(tolerance > 0);  // also catches NaN
    // Cells twice the tolerance wide: a point's tolerance box then overlaps at most two cells per axis, so
    // 8 probes instead of the 27 that tolerance-wide cells need. Cell indices are clamped so far-out or
    // non-finite coordinates cannot overflow the conversion; clamped points share a cell, which costs
    // time but never a wrong answer, because distances are always checked. In exact mode a cell is one
    // position, keyed by the coordinates' bits (with -0 folded into 0).
    double cellSize = 2 * tolerance;
    auto cellOf = [&](double x) {
        constexpr double kLimit = 4.0e18;
        double cell = std::floor(x / cellSize);
        return int64_t(std::clamp(std::isnan(cell) ? 0.0 : cell, -kLimit, kLimit));
    };
    using Key = std::array<int64_t, 3>;
    auto keyOf = [&](const Vector3d& p) {
        Key k;
        for (int a = 0; a < 3; ++a) k[size_t(a)] = exact ? std::bit_cast<int64_t>(p[a] + 0.0) : cellOf(p[a]);
        return k;
    };
    auto hash = [](const Key& k) {
        uint64_t h = uint64_t(k[0]) * 0x9E3779B97F4A7C15ull;
        h = (h ^ (h >> 29)) + uint64_t(k[1]) * 0xBF58476D1CE4E5B9ull;
        h = (h ^ (h >> 31)) + uint64_t(k[2]) * 0x94D049BB133111EBull;
        return h ^ (h >> 32);
    };
    auto close = [&](const Vector3d& a, const Vector3d& b) {
        // Dividing first keeps tiny tolerances from squaring to zero.
        return exact ? a == b : ((a - b) / tolerance).squaredNorm() <= 1.0;
    };

    // Open addressing from a cell to the latest kept point in it; the cell's other kept points chain
    // through `next`. A slot's key is recomputed from its point rather than stored, halving the memory.
    constexpr size_t kNone = size_t(-1);
    size_t capacity = 16;
    while (capacity < 2 * pos.size()) capacity *= 2;
    std::vector<size_t> table(capacity, kNone), next;
    next.reserve(pos.size());
    auto slotOf = [&](const Key& key) -> size_t& {
        size_t s = hash(key) & (capacity - 1);
        while (table[s] != kNone && keyOf(pos[table[s]]) != key) s = (s + 1) & (capacity - 1);
        return table[s];
    };

    size_t kept = 0;
    for (size_t i = 0; i < pos.size(); ++i) {
        const Vector3d p = pos[i];
        Key lo = keyOf(p), hi = lo;
        if (!exact) {
            for (size_t a = 0; a < 3; ++a) {
                lo[a] = cellOf(p[Eigen::Index(a)] - tolerance);
                hi[a] = cellOf(p[Eigen::Index(a)] + tolerance);
            }
        }
        bool duplicate = false;
        for (int64_t x = lo[0]; x <= hi[0] && !duplicate; ++x)
            for (int64_t y = lo[1]; y <= hi[1] && !duplicate; ++y)
                for (int64_t z = lo[2]; z <= hi[2] && !duplicate; ++z)
                    for (size_t j = slotOf({x, y, z}); j != kNone && !duplicate; j = next[j])
                        duplicate = close(pos[j], p);
        if (duplicate) continue;
        // Kept points are compacted in place (kept <= i), so the table holds output indices.
        pos[kept] = p;
        if (moveNormals) points.normals[kept] = points.normals[i];
        size_t& head = slotOf(keyOf(p));
        next.push_back(head);
        head = kept++;
    }
    size_t merged = pos.size() - kept;
    pos.resize(kept);
    if (moveNormals) points.normals.resize(kept);
    return merged;
}

std::vector<size_t> farthestPointSample(const std::vector<Vector3d>& positions, size_t count) {
    size_t n = positions.size();
    std::vector<size_t> picked;
    if (count >= n) {
        for (size_t i = 0; i < n; ++i) picked.push_back(i);
        return picked;
    }
    if (count == 0) return picked;
    auto less = [](const Vector3d& a, const Vector3d& b) {
        return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
    };
    size_t first = 0;
    for (size_t i = 1; i < n; ++i)
        if (less(positions[i], positions[first])) first = i;

    // distance[i]: squared distance from i to the nearest picked point; -1 once i is picked.
    std::vector<double> distance(n, std::numeric_limits<double>::infinity());
    picked.reserve(count);
    size_t current = first;
    for (;;) {
        picked.push_back(current);
        distance[current] = -1;
        if (picked.size() == count) break;
        size_t best = n;
        double bestDistance = -1;
        for (size_t i = 0; i < n; ++i) {
            if (distance[i] < 0) continue;
            double d = (positions[i] - positions[current]).squaredNorm();
            if (d < distance[i]) distance[i] = d;
            if (distance[i] > bestDistance) {  // strict: ties keep the lowest index
                bestDistance = distance[i];
                best = i;
            }
        }
        // Only reachable with NaN coordinates: take the lowest index not yet picked.
        if (best == n)
            best = size_t(std::find_if(distance.begin(), distance.end(), [](double d) { return !(d < 0); }) -
                          distance.begin());
        current = best;
    }
    return picked;
}

}  // namespace ink
