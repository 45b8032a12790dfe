// The OFF reader (Geomview's Object File Format and its common variants): a header keyword (OFF, COFF, NOFF,
// CNOFF, NCOFF, STOFF, ...), the counts, one vertex a line, one face a line. docs/file-formats.md says what is
// read.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <string_view>

namespace ink::io {
namespace {

using Eigen::Vector3d;

// What the header keyword says each vertex line carries: [ST][C][N][4][n]OFF in Geomview's order of
// prefixes; the data on a vertex line come as x y z, then the normal, then the colour, then the texture
// coordinates.
struct OffKind {
    bool texture = false, colour = false, normal = false;
};

bool offKind(std::string_view word, OffKind& kind, std::string& unsupported) {
    if (word.size() < 3 || word.substr(word.size() - 3) != "OFF") return false;
    std::string_view prefix = word.substr(0, word.size() - 3);
    if (prefix.substr(0, 2) == "ST") {
        kind.texture = true;
        prefix.remove_prefix(2);
    }
    if (!prefix.empty() && prefix[0] == 'C') {
        kind.colour = true;
        prefix.remove_prefix(1);
    }
    if (!prefix.empty() && prefix[0] == 'N') {
        kind.normal = true;
        prefix.remove_prefix(1);
    }
    // NCOFF is written by some tools for CNOFF.
    if (!kind.colour && !prefix.empty() && prefix[0] == 'C') {
        kind.colour = true;
        prefix.remove_prefix(1);
    }
    if (prefix == "4" || prefix == "n" || prefix == "4n") {
        unsupported = quoted(word);
        unsupported += " (homogeneous or n-dimensional vertices) is not supported";
        return true;
    }
    return prefix.empty();
}

// The next line with something on it, comments ('#' to the end of the line) removed, split into fields.
bool nextFields(Lines& lines, std::vector<std::string_view>& fields) {
    std::string_view line;
    while (lines.next(line)) {
        splitFields(line.substr(0, line.find('#')), fields);
        if (!fields.empty()) return true;
    }
    return false;
}

uint64_t count(std::string_view field, const char* what, const std::string& name, const std::string& where) {
    int64_t v;
    if (!toInt(field, v) || v < 0)
        fail(name, where + ": the " + what + " count " + quoted(field) + " is not a non-negative integer");
    if (uint64_t(v) > kMaxElements)
        fail(name, where + ": the header claims " + std::to_string(v) + " " + what + "; the limit is " +
                       std::to_string(kMaxElements));
    return uint64_t(v);
}

}  // namespace

OrientedPoints parseOff(const std::string& bytes, const std::string& name) {
    std::string_view text(bytes);
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte order mark
    rejectBinary(text, name);
    Lines lines(text);
    std::vector<std::string_view> f;
    if (!nextFields(lines, f)) fail(name, "empty file: expected an OFF header");
    OffKind kind;
    std::string unsupported;
    if (!offKind(f[0], kind, unsupported))
        fail(name, lineName(lines.number()) + ": not an OFF file (the header is " + quoted(f[0]) +
                       ", expected OFF, COFF, NOFF or CNOFF)");
    if (!unsupported.empty()) fail(name, lineName(lines.number()) + ": " + unsupported);
    if (f.size() > 1 && f[1] == "BINARY") fail(name, lineName(lines.number()) + ": binary OFF is not supported");
    // The counts follow the keyword on its line, or come on the next line with something on it.
    if (f.size() == 1 && !nextFields(lines, f)) fail(name, "no vertex and face counts after the header");
    size_t first = f.size() > 1 && offKind(f[0], kind, unsupported) ? 1 : 0;
    std::string where = lineName(lines.number());
    size_t counts = f.size() - first;
    if (counts < 2 || counts > 3)
        fail(name, where + ": expected the counts 'VERTICES FACES EDGES', found " + std::to_string(counts) + " fields");
    uint64_t vertices = count(f[first], "vertices", name, where);
    uint64_t faces = count(f[first + 1], "faces", name, where);
    if (counts == 3) count(f[first + 2], "edges", name, where);  // unused, but a number
    if (vertices == 0) fail(name, where + ": no vertices");
    // Each value needs at least a character and a separator: refuse what the rest cannot hold before allocating.
    if (vertices * 3 + faces * 4 > lines.remaining() + 1)
        fail(name, "truncated: the header declares " + std::to_string(vertices) + " vertices and " +
                       std::to_string(faces) + " faces but only " + std::to_string(lines.remaining()) +
                       " bytes are left");

    size_t fixed = 3 + (kind.normal ? 3 : 0) + (kind.texture ? 2 : 0);
    OrientedPoints points;
    points.positions.reserve(vertices);
    if (kind.normal) points.normals.reserve(vertices);
    std::vector<size_t> lineOf;
    lineOf.reserve(vertices);
    for (uint64_t i = 0; i < vertices; ++i) {
        if (!nextFields(lines, f))
            fail(name,
                 "truncated: expected " + std::to_string(vertices) + " vertices, file ends after " + std::to_string(i));
        std::string at = lineName(lines.number()) + " (vertex " + std::to_string(i) + ")";
        // A colour is 3 or 4 values (r g b [a]), or one colour-map index.
        bool ok = f.size() == fixed ||
                  (kind.colour && f.size() >= fixed + 1 && f.size() <= fixed + 4 && f.size() != fixed + 2);
        if (!ok)
            fail(name, at + ": expected " + std::to_string(fixed) +
                           (kind.colour ? " numbers and a colour" : " numbers") + ", found " +
                           std::to_string(f.size()) + " fields");
        double v[6] = {};
        for (size_t k = 0; k < f.size(); ++k) {
            double value;
            if (!toDouble(f[k], value)) fail(name, at + ": " + quoted(f[k]) + " is not a number");
            if (k < 6) v[k] = value;
        }
        points.positions.emplace_back(v[0], v[1], v[2]);
        if (kind.normal) points.normals.emplace_back(v[3], v[4], v[5]);
        lineOf.push_back(lines.number());
    }
    auto vertexName = [&](size_t i) { return "vertex " + std::to_string(i) + " (" + lineName(lineOf[i]) + ")"; };

    Polygons polygons;
    for (uint64_t i = 0; i < faces; ++i) {
        if (!nextFields(lines, f))
            fail(name, "truncated: expected " + std::to_string(faces) + " faces, file ends after " + std::to_string(i));
        std::string at = lineName(lines.number()) + " (face " + std::to_string(i) + ")";
        int64_t n;
        if (!toInt(f[0], n) || n < 0)
            fail(name, at + ": the vertex count " + quoted(f[0]) + " is not a non-negative integer");
        if (n < 3) fail(name, at + ": has " + std::to_string(n) + " vertices; at least 3 are needed");
        // After the indices, an optional colour: 0 to 4 values.
        if (uint64_t(n) + 1 > f.size())
            fail(name, at + ": claims " + std::to_string(n) + " vertices but the line has " +
                           std::to_string(f.size() - 1) + " more fields");
        if (f.size() > uint64_t(n) + 5)
            fail(name, at + ": " + std::to_string(f.size() - 1 - uint64_t(n)) +
                           " fields after the vertex indices; at most 4 (a colour) are allowed");
        for (int64_t k = 1; k <= n; ++k) {
            int64_t index;
            if (!toInt(f[size_t(k)], index)) fail(name, at + ": " + quoted(f[size_t(k)]) + " is not a vertex index");
            if (index < 0 || uint64_t(index) >= vertices)
                fail(name, at + ": vertex index " + std::to_string(index) + " is out of range (the file has " +
                               std::to_string(vertices) + " vertices)");
            polygons.indices.push_back(uint32_t(index));
        }
        for (size_t k = size_t(n) + 1; k < f.size(); ++k) {
            double value;
            if (!toDouble(f[k], value)) fail(name, at + ": " + quoted(f[k]) + " is not a number");
        }
        polygons.sizes.push_back(uint32_t(n));
    }
    if (nextFields(lines, f))
        fail(name, lineName(lines.number()) + ": more data after the " + std::to_string(faces) +
                       " faces the header declares");

    if (kind.normal) {
        appendTriangles(polygons, {}, 0, points.triangles);
        replaceZeroNormals(points, name);
        finish(points, name, vertexName, polygons.sizes.empty() ? ZeroNormal::Estimated : ZeroNormal::Refused);
        return points;
    }
    if (polygons.sizes.empty()) {  // a point cloud without normals: the fit estimates them
        points.normals.assign(points.positions.size(), Vector3d::Zero());
        finish(points, name, vertexName, ZeroNormal::Estimated);
        return points;
    }
    // As PLY and OBJ: vertices no face uses are dropped, and a used one whose faces have no area is an error.
    return meshPoints(points.positions, polygons, name, vertexName);
}

}  // namespace ink::io
