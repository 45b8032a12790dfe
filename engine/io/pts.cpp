// The oriented point text reader (.pts, .xyzn, .txt, .xyz, .pwn): one point a line, x y z nx ny nz, '#' starts
// a comment; .xyz and .pwn may start with a line holding the number of points, as some writers put there.
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
    size_t declaredLine = 0;
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        splitFields(line, fields);
        if (fields.empty()) continue;
        std::string where = lineName(lines.number());
        if (countLine && points.positions.empty() && declared < 0 && fields.size() == 1) {
            if (!toInt(fields[0], declared) || declared < 0)
                fail(name,
                     where + ": expected a point count or 6 numbers (x y z nx ny nz), found " + quoted(fields[0]));
            declaredLine = lines.number();
            continue;
        }
        if (fields.size() != 6)
            fail(name, where + ": expected 6 numbers (x y z nx ny nz), found " + std::to_string(fields.size()) +
                           " fields" + (fields.size() == 3 ? " (points without normals cannot be oriented)" : ""));
        double v[6];
        for (size_t k = 0; k < 6; ++k)
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
    finish(points, name, [&](size_t i) { return lineName(lineOf[i]); });
    return points;
}

}  // namespace ink::io
