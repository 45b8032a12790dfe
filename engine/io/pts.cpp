// The point text reader (.pts, .xyzn, .txt, .xyz, .pwn): one point a line, x y z nx ny nz or x y z alone (the fit
// then estimates the normals), '#' starts a comment; .xyz and .pwn may start with a line holding the number of
// points, as some writers put there.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <string_view>

namespace ink::io {

OrientedPoints parsePts(const std::string& bytes, const std::string& name, bool countLine) {
    rejectBinary(bytes, name);
    OrientedPoints points;
    std::vector<size_t> lineOf;
    std::vector<std::string_view> fields;
    Lines lines(bytes);
    std::string_view line;
    int64_t declared = -1;
    size_t declaredLine = 0, width = 0;  // numbers a point: 6, or 3 without normals
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        splitFields(line, fields);
        if (fields.empty()) continue;
        std::string where = lineName(lines.number());
        if (countLine && points.positions.empty() && declared < 0 && fields.size() == 1) {
            if (!toInt(fields[0], declared) || declared < 0)
                fail(name,
                     where + ": expected a point count, or a point's 6 numbers (x y z nx ny nz) or 3 (x y z), found " +
                         quoted(fields[0]));
            declaredLine = lines.number();
            continue;
        }
        // Every point as the first: x y z nx ny nz, or x y z alone (a cloud without normals; the fit estimates them).
        if (width == 0 && (fields.size() == 3 || fields.size() == 6)) width = fields.size();
        if (fields.size() != width)
            fail(name,
                 where + ": expected " +
                     (width == 3 ? std::string("3 numbers (x y z, as the first point)")
                                 : std::string("6 numbers (x y z nx ny nz)") + (width == 0 ? " or 3 (x y z)" : "")) +
                     ", found " + std::to_string(fields.size()) + " fields");
        double v[6] = {};
        for (size_t k = 0; k < width; ++k)
            if (!toDouble(fields[k], v[k])) fail(name, where + ": " + quoted(fields[k]) + " is not a number");
        if (points.positions.size() >= kMaxElements)
            fail(name, where + ": more than " + std::to_string(kMaxElements) + " points");
        points.positions.emplace_back(v[0], v[1], v[2]);
        points.normals.emplace_back(v[3], v[4], v[5]);
        lineOf.push_back(lines.number());
    }
    if (declared >= 0 && uint64_t(declared) != points.positions.size())
        fail(name, lineName(declaredLine) + ": the count line says " + std::to_string(declared) +
                       " points, the file has " + std::to_string(points.positions.size()));
    finish(
        points, name, [&](size_t i) { return lineName(lineOf[i]); }, ZeroNormal::Estimated);
    return points;
}

}  // namespace ink::io
