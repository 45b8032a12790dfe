// The OBJ reader: one strict pass over the v, vn and f lines (every other line is ignored), then the
// normals faces name, or area-weighted ones where they name none. docs/file-formats.md says what is read.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string_view>

namespace ink::io {
namespace {

using Eigen::Vector3d;

// The file as read: coordinates in double with the line of each (for messages), and the faces with, per
// corner, the index of the normal it names or -1.
struct ObjScan {
    std::vector<Vector3d> v, vn;
    std::vector<size_t> vLine, vnLine;
    Polygons faces;
    std::vector<int> cornerNormals;
};

// Splits a face corner "v", "v/vt", "v/vt/vn" or "v//vn" into its indices (0 where absent), refusing
// anything else, so that a malformed corner is an error rather than index 0 or a prefix of a number.
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
    // Positive indices may point forward (the OBJ specification allows it), so they are checked at the end;
    // only those beyond the count so far need remembering.
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
        // The same blanks as between fields (splitFields): a form feed after 'v' dropped the vertex.
        constexpr const char* kBlanks = " \t\r\f\v";
        size_t at = line.find_first_not_of(kBlanks);
        if (at == std::string_view::npos) continue;
        line.remove_prefix(at);
        auto where = [&] { return lineName(lines.number()); };
        // A keyword alone on its line counts too ("v" then a lone '\r', which ends the line): it is refused for
        // its missing numbers rather than skipped.
        auto space = [&](size_t i) {
            return line.size() == i ||
                   (line.size() > i && std::string_view(kBlanks).find(line[i]) != std::string_view::npos);
        };
        bool vertex = line[0] == 'v' && space(1);
        bool normal = line[0] == 'v' && line.size() > 1 && line[1] == 'n' && space(2);
        bool face = line[0] == 'f' && space(1);
        if (!vertex && !normal && !face) continue;
        splitFields(line.substr(std::min(line.size(), size_t(vertex || face ? 2 : 3))), fields);

        if (vertex || normal) {
            // A trailing comment is allowed.
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
            continue;
        }

        if (fields.size() < 3)
            fail(name, where() + ": face has " + std::to_string(fields.size()) + " vertices; at least 3 are needed");
        // No real mesh comes near it; the limit dates from a reader that kept polygon sizes in a byte, and
        // stays so that the files accepted do not change.
        if (fields.size() > 255)
            fail(name,
                 where() + ": face has " + std::to_string(fields.size()) + " vertices; at most 255 are supported");
        for (std::string_view corner : fields) {
            int64_t index[3];
            size_t count;
            if (!splitCorner(corner, index, count))
                fail(name, where() + ": " + quoted(corner) +
                               " is not a face vertex (v, v/vt, v/vt/vn or v//vn; indices are nonzero integers)");
            int64_t resolved[3] = {-1, -1, -1};
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
                // Negative indices count back from the latest one read; positive ones count from 1.
                resolved[slot] = i < 0 ? have + i : i - 1;
            }
            // The texture coordinate index is not used, but other readers hold it in an int; one that does
            // not fit marks a broken file.
            constexpr int64_t kMaxInt = std::numeric_limits<int>::max();
            if (count >= 2 && (index[1] > kMaxInt || index[1] < -kMaxInt))
                fail(name,
                     where() + ": face texture coordinate index " + std::to_string(index[1]) + " is out of range");
            // A forward index beyond the end may not fit here, but it is refused below before any use.
            scan.faces.indices.push_back(uint32_t(resolved[0]));
            scan.cornerNormals.push_back(int(resolved[2]));
        }
        scan.faces.sizes.push_back(uint32_t(fields.size()));
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

}  // namespace

OrientedPoints parseObj(const std::string& bytes, const std::string& name) {
    ObjScan scan = scanObj(bytes, name);
    if (scan.v.empty()) fail(name, "no vertices");

    OrientedPoints out;
    if (scan.faces.sizes.empty()) {
        // A point cloud written as OBJ: normals can only pair with vertices one to one, in order; without any, the
        // fit estimates them.
        if (!scan.vn.empty() && scan.vn.size() != scan.v.size())
            fail(name, "has no faces, and its " + std::to_string(scan.vn.size()) + " normals do not pair up with its " +
                           std::to_string(scan.v.size()) + " vertices");
        out.positions = scan.v;
        out.normals = scan.vn.empty() ? std::vector<Vector3d>(scan.v.size(), Vector3d::Zero()) : scan.vn;
        finish(
            out, name,
            [&](size_t i) { return "vertex " + std::to_string(i + 1) + " (" + lineName(scan.vLine[i]) + ")"; },
            ZeroNormal::Estimated);
        return out;
    }

    size_t n = scan.v.size();
    std::vector<Vector3d> area(n, Vector3d::Zero()), given(n, Vector3d::Zero());
    std::vector<char> used(n, 0), hasGiven(n, 0);
    addAreaNormals(scan.v, scan.faces, area, used);
    // Normals named by faces win over computed ones; a vertex met with several is given their average. A zero one
    // (exporters write 0 0 0 for a normal they did not compute) is passed over: its vertex takes its faces'
    // normal, unless another corner gives it one.
    std::vector<char> zeroNamed(n, 0);
    for (size_t k = 0; k < scan.cornerNormals.size(); ++k) {
        int ni = scan.cornerNormals[k];
        if (ni < 0) continue;
        const Vector3d& vn = scan.vn[size_t(ni)];
        double length = safeNorm(vn);
        if (!(length > kZeroNormal)) {
            zeroNamed[scan.faces.indices[k]] = 1;
            continue;
        }
        uint32_t vi = scan.faces.indices[k];
        given[vi] += safeNormalized(vn);
        hasGiven[vi] = 1;
    }

    // Whether any face around a vertex has area (not only their sum: windings that cancel are refused below).
    const double diagonal = usedDiagonal(scan.v, used);
    std::vector<char> faceArea(n, 0);
    if (std::find(zeroNamed.begin(), zeroNamed.end(), 1) != zeroNamed.end()) {
        size_t at = 0;
        for (uint32_t size : scan.faces.sizes) {
            const uint32_t* idx = scan.faces.indices.data() + at;
            at += size;
            Vector3d sum = Vector3d::Zero();
            for (uint32_t k = 1; k + 1 < size; ++k)
                sum += (scan.v[idx[k]] - scan.v[idx[0]]).cross(scan.v[idx[k + 1]] - scan.v[idx[0]]);
            if (!zeroArea(sum, diagonal))
                for (uint32_t k = 0; k < size; ++k) faceArea[idx[k]] = 1;
        }
    }
    std::vector<Vector3d> normal(n, Vector3d::Zero());
    std::vector<char> deferred(n, 0);
    size_t replaced = 0, borrowed = 0, dropped = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!used[i]) continue;
        auto where = [&] { return "vertex " + std::to_string(i + 1) + " (" + lineName(scan.vLine[i]) + ")"; };
        if (hasGiven[i]) {
            normal[i] = given[i];
        } else if (zeroNamed[i] && !faceArea[i]) {
            deferred[i] = 1;  // no normal in the file and no face area: its neighbours', below
        } else {
            replaced += zeroNamed[i];
            settleAreaNormal(area[i], diagonal, name, where);
            normal[i] = area[i];
        }
    }
    // A vertex the file gives a zero normal and whose faces have no area (a sliver's corner) takes the normals of
    // its faces' other vertices, so that the mesh keeps its faces (dropping them would open a hole whose rim is a
    // boundary line); with no such neighbour it goes, with its faces.
    if (std::find(deferred.begin(), deferred.end(), 1) != deferred.end()) {
        std::vector<Vector3d> around(n, Vector3d::Zero());
        size_t at = 0;
        for (uint32_t size : scan.faces.sizes) {
            const uint32_t* idx = scan.faces.indices.data() + at;
            at += size;
            Vector3d sum = Vector3d::Zero();
            for (uint32_t k = 0; k < size; ++k)
                if (!deferred[idx[k]]) sum += safeNormalized(normal[idx[k]]);
            for (uint32_t k = 0; k < size; ++k)
                if (deferred[idx[k]]) around[idx[k]] += sum;
        }
        for (size_t i = 0; i < n; ++i) {
            if (!deferred[i]) continue;
            if (around[i].allFinite() && safeNorm(around[i]) > kZeroNormal) {
                normal[i] = around[i];
                ++borrowed;
            } else {
                used[i] = 0;
                ++dropped;
            }
        }
    }
    std::vector<size_t> vertexOf;
    std::vector<uint32_t> renumber(n, kDropped);
    for (size_t i = 0; i < n; ++i) {
        if (!used[i]) continue;
        renumber[i] = uint32_t(vertexOf.size());
        vertexOf.push_back(i);
        out.positions.push_back(scan.v[i]);
        out.normals.push_back(normal[i]);
    }
    if (replaced > 0) note(zeroNormalsNote(name, replaced, "", "faces'"));
    if (borrowed > 0) note(zeroNormalsNote(name, borrowed, " and faces without area", "neighbours'"));
    if (out.positions.empty() && dropped > 0)
        fail(name, "every vertex the faces use has a zero normal in the file and faces without area");
    if (dropped > 0)
        note(name + ": dropped " + std::to_string(dropped) + (dropped == 1 ? " vertex" : " vertices") +
             " with a zero normal in the file, faces without area and no neighbour with a normal");
    // Several given normals can still cancel out; finish() calls that a zero normal too.
    finish(out, name, [&](size_t i) {
        return "vertex " + std::to_string(vertexOf[i] + 1) + " (" + lineName(scan.vLine[vertexOf[i]]) + ")";
    });
    appendTriangles(scan.faces, renumber, 0, out.triangles);
    return out;
}

}  // namespace ink::io
