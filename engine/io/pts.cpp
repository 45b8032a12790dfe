// The oriented point text reader (.pts, .xyzn, .txt): one point a line, x y z nx ny nz, '#' starts a comment.
#include "common.h"
#include "normals.h"
#include "readers.h"
#include "text.h"

#include <string_view>

namespace ink::io {

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

}  // namespace ink::io
