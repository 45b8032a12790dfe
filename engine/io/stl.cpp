// The STL reader, ASCII and binary: a soup of triangles whose corners are welded (bit-identical positions
// merged) so that each vertex gets the area-weighted normal of the triangles around it. The facet normals the
// file holds are read but not used: writers often leave them zero or wrong, and the winding says the same.
// docs/file-formats.md says what is read.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <bit>
#include <cctype>
#include <cstring>
#include <string_view>

namespace ink::io {
namespace {

using Eigen::Vector3d;

constexpr uint64_t kHeaderBytes = 84, kRecordBytes = 50;

bool startsWithSolid(std::string_view text) {
    size_t at = text.find_first_not_of(" \t\r\n");
    if (at == std::string_view::npos || text.size() - at < 5) return false;
    for (size_t k = 0; k < 5; ++k)
        if (std::tolower(static_cast<unsigned char>(text[at + k])) != "solid"[k]) return false;
    return text.size() - at == 5 || std::isspace(static_cast<unsigned char>(text[at + 5]));
}

float readFloat(const char* p) {
    uint32_t bits;
    std::memcpy(&bits, p, 4);
    if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
    return std::bit_cast<float>(bits);
}

// A triangle soup: three corners a triangle, with a name for each triangle in messages.
struct Soup {
    std::vector<Vector3d> corners;
    std::vector<size_t> where;  // binary: the facet number; ascii: the line of the facet's first vertex
};

void readBinary(const std::string& bytes, const std::string& name, Soup& soup) {
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    if (count > kMaxElements)
        fail(name, "binary STL header claims " + std::to_string(count) + " triangles; the limit is " +
                       std::to_string(kMaxElements));
    soup.corners.reserve(size_t(count) * 3);
    for (uint32_t t = 0; t < count; ++t) {
        const char* record = bytes.data() + kHeaderBytes + uint64_t(t) * kRecordBytes;
        for (int c = 0; c < 3; ++c) {
            const char* p = record + 12 + 12 * c;  // after the facet normal
            Vector3d v(readFloat(p), readFloat(p + 4), readFloat(p + 8));
            if (!v.allFinite()) fail(name, "facet " + std::to_string(t) + ": coordinate is not finite " + str(v));
            soup.corners.push_back(v);
        }
        soup.where.push_back(t);
    }
}

// ASCII STL as a stream of words: solid NAME, then facets (facet normal N N N / outer loop / vertex X Y Z
// three times / endloop / endfacet), then endsolid NAME; several solids may follow one another. Keywords are
// read case-insensitively; a solid's name runs to the end of its line.
class AsciiStl {
public:
    AsciiStl(const std::string& bytes, const std::string& name) : lines_(bytes), name_(name) {}

    void read(Soup& soup) {
        bool any = false;
        while (word()) {
            expect("solid");
            skipLine();  // the name
            any = true;
            for (;;) {
                if (!word()) fail(name_, "truncated: the file ends inside a solid (no 'endsolid')");
                if (is("endsolid")) {
                    skipLine();
                    break;
                }
                expect("facet");
                next("normal");
                for (int k = 0; k < 3; ++k) number();  // checked, not used
                next("outer");
                next("loop");
                size_t line = 0;
                for (int c = 0; c < 3; ++c) {
                    if (!word()) truncated();
                    if (is("endloop"))
                        fail(name_, where() + ": a facet with " + std::to_string(c) + " vertices; STL facets have 3");
                    expect("vertex");
                    if (c == 0) line = lines_.number();
                    Vector3d v;
                    for (int k = 0; k < 3; ++k) v[k] = number();
                    if (!v.allFinite()) fail(name_, where() + ": coordinate is not finite " + str(v));
                    soup.corners.push_back(v);
                }
                next("endloop");
                next("endfacet");
                soup.where.push_back(line);
                if (soup.where.size() > kMaxElements)
                    fail(name_, where() + ": more than " + std::to_string(kMaxElements) + " triangles");
            }
        }
        if (!any) fail(name_, "empty file: no 'solid'");
    }

private:
    // The next word, across lines; false at the end of the file.
    bool word() {
        while (field_ == fields_.size()) {
            std::string_view line;
            if (!lines_.next(line)) return false;
            splitFields(line, fields_);
            field_ = 0;
        }
        word_ = fields_[field_++];
        return true;
    }
    void skipLine() { field_ = fields_.size(); }
    bool is(const char* keyword) const {
        size_t n = std::strlen(keyword);
        if (word_.size() != n) return false;
        for (size_t k = 0; k < n; ++k)
            if (std::tolower(static_cast<unsigned char>(word_[k])) != keyword[k]) return false;
        return true;
    }
    void expect(const char* keyword) {
        if (!is(keyword)) fail(name_, where() + ": expected '" + keyword + "', found " + quoted(word_));
    }
    void next(const char* keyword) {
        if (!word()) truncated();
        expect(keyword);
    }
    double number() {
        if (!word()) truncated();
        double v;
        if (!toDouble(word_, v)) fail(name_, where() + ": " + quoted(word_) + " is not a number");
        return v;
    }
    std::string where() const { return lineName(lines_.number()); }
    [[noreturn]] void truncated() const { fail(name_, "truncated: the file ends inside a facet"); }

    Lines lines_;
    const std::string& name_;
    std::vector<std::string_view> fields_;
    size_t field_ = 0;
    std::string_view word_;
};

}  // namespace

OrientedPoints parseStl(const std::string& bytes, const std::string& name) {
    // Binary when the size is exactly what the count at byte 80 says, as other readers decide: binary files
    // often begin with "solid" too. Otherwise ASCII if it begins with "solid", else a broken binary file.
    bool binary = false;
    uint64_t declared = 0;
    if (bytes.size() >= kHeaderBytes) {
        uint32_t count;
        std::memcpy(&count, bytes.data() + 80, 4);
        if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
        declared = count;
        binary = kHeaderBytes + declared * kRecordBytes == bytes.size();
    }
    Soup soup;
    if (binary) {
        readBinary(bytes, name, soup);
    } else if (startsWithSolid(bytes)) {
        rejectBinary(bytes, name);  // a binary STL whose size is off would fail here, with a line
        AsciiStl(bytes, name).read(soup);
    } else if (bytes.size() < kHeaderBytes) {
        fail(name, "not an STL file: " + std::to_string(bytes.size()) +
                       " bytes, too short for a binary STL (84 bytes of header and count) and not ASCII ('solid')");
    } else {
        fail(name, "binary STL: the header declares " + std::to_string(declared) + " triangles, which take " +
                       std::to_string(kHeaderBytes + declared * kRecordBytes) + " bytes, but the file has " +
                       std::to_string(bytes.size()) + " (truncated or not an STL file)");
    }
    if (soup.where.empty()) fail(name, "no triangles");

    std::vector<Vector3d> vertices;
    std::vector<uint32_t> index = weld(soup.corners, vertices);
    Polygons triangles;
    triangles.indices = std::move(index);
    triangles.sizes.assign(soup.where.size(), 3);
    std::vector<size_t> kept;
    size_t degenerate = 0;
    OrientedPoints points = areaNormalPoints(vertices, triangles, kept, degenerate);
    if (points.positions.empty()) fail(name, "every triangle has zero area: no vertex has a normal");
    if (degenerate > 0)
        note(name + ": dropped " + std::to_string(degenerate) + " vertex" + (degenerate == 1 ? "" : "es") +
             " whose triangles all have zero area");
    finish(points, name, [&](size_t i) { return "vertex " + std::to_string(kept[i]); });
    return points;
}

}  // namespace ink::io
