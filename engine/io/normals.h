// How the readers turn what they read into oriented points: area-weighted vertex normals for meshes that
// have none, and the final check and normalization every reader ends with.
#pragma once

#include "io/points.h"
#include "io/text.h"

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace ink::io {

// Normals read from a file (already meant to be unit length) shorter than this count as zero.
constexpr double kZeroNormal = 1e-12;

// Polygons as a flat index list plus sizes (any size >= 3), as read: indices into the file's vertices.
struct Polygons {
    std::vector<uint32_t> indices;
    std::vector<uint32_t> sizes;
};

// Marks a vertex a reader dropped, in a renumbering for appendTriangles.
constexpr uint32_t kDropped = UINT32_MAX;

// Fan-triangulates `polygons` (k, k+1 around corner 0, as addAreaNormals sums them) onto `out`, each index i
// becoming renumber[i] + offset (i + offset where `renumber` is empty). A triangle with a dropped corner is left
// out.
void appendTriangles(const Polygons& polygons, const std::vector<uint32_t>& renumber, uint32_t offset,
                     std::vector<Triangle>& out);

// Adds each polygon's area vector to its vertices and marks them used. For a fan-triangulated polygon the
// sum of the fan's edge cross products is twice its area times its normal, so big faces weigh more than
// slivers, and non-convex polygons still come out right.
void addAreaNormals(const std::vector<Eigen::Vector3d>& positions, const Polygons& polygons,
                    std::vector<Eigen::Vector3d>& sums, std::vector<char>& used);

// Length of v without overflow or underflow in the squares.
double safeNorm(const Eigen::Vector3d& v);

// v brought to unit length the same way: divided by its largest component first, so that a vector whose
// length overflows a double (a face of 1e308 across) still gives its direction. Zero or non-finite v is
// returned as it is.
Eigen::Vector3d safeNormalized(const Eigen::Vector3d& v);

// The bounding-box diagonal of the vertices faces use: the scale against which area normals are judged.
double usedDiagonal(const std::vector<Eigen::Vector3d>& positions, const std::vector<char>& used);

// Area sums scale with the model's size squared, so "zero" means tiny next to the squared diagonal (the
// division order avoids overflowing the square). The sum is then brought to unit length so that finish()
// can treat it like a normal read from a file. `where()` names the vertex, and is called only to fail.
inline bool zeroArea(const Eigen::Vector3d& n, double diagonal) {
    double length = safeNorm(n);
    return std::isfinite(length) && (length == 0 || (std::isfinite(diagonal) && length / diagonal / diagonal <= 1e-12));
}
template <class Where>
void settleAreaNormal(Eigen::Vector3d& n, double diagonal, const std::string& name, Where where) {
    if (!std::isfinite(safeNorm(n))) return;  // finish() reports it
    if (zeroArea(n, diagonal))
        fail(name, where() + ": normal is zero (the faces around it have no area, or their windings cancel)");
    n = safeNormalized(n);
}

// A mesh whose file gives normals may give some as zero (exporters write 0 0 0 for a normal they did not
// compute): each such vertex that `points.triangles` use takes its triangles' area-weighted normal instead, unless
// that is zero too (then finish() refuses it). Non-finite normals are left for finish() to refuse. Notes how many
// were replaced (none: no note) and returns that count.
size_t replaceZeroNormals(OrientedPoints& points, const std::string& name);
// "NAME: 3 vertices with a zero normal in the file[ALSO] take their WHOSE normal" (1: "vertex ... takes its").
std::string zeroNormalsNote(const std::string& name, size_t count, const char* also, const char* whose);

// Merges positions that are bit for bit the same (+0 and -0 alike), as triangle soups (STL, glTF without
// normals) need before their vertices can have normals: `unique` gets each distinct position once, in order of
// first appearance; the result gives, for each input position, the index of its copy in `unique`.
std::vector<uint32_t> weld(const std::vector<Eigen::Vector3d>& positions, std::vector<Eigen::Vector3d>& unique);

// For welded soups: the vertices the polygons use, in order, with their area-weighted normals (unit length).
// A vertex whose polygons have no area (only slivers and repeated corners around it, common in STL) is dropped
// rather than refused, and counted in `degenerate`; `kept` gets the index of each vertex kept. The polygons
// come out as triangles in the new numbering, those touching a dropped vertex left out.
OrientedPoints areaNormalPoints(const std::vector<Eigen::Vector3d>& positions, const Polygons& polygons,
                                std::vector<size_t>& kept, size_t& degenerate);

// What a zero normal means to finish(): a mesh's vertex must have one (its faces' replaced a zero one before), a
// point cloud's point may lack it (a file without normals, or a 0 0 0 one): it stays zero, and the fit estimates it
// from the point's neighbours (estimateNormals, surface/clean.h).
enum class ZeroNormal { Refused, Estimated };

// Checks and normalizes; `where(i)` names point i for messages ("vertex 17", "line 4").
template <class Where>
void finish(OrientedPoints& points, const std::string& name, Where where, ZeroNormal zero = ZeroNormal::Refused) {
    if (points.positions.empty()) fail(name, "no vertices");
    for (size_t i = 0; i < points.positions.size(); ++i) {
        const Eigen::Vector3d& p = points.positions[i];
        Eigen::Vector3d& n = points.normals[i];
        if (!p.allFinite()) fail(name, where(i) + ": coordinate is not finite " + str(p));
        if (!n.allFinite()) fail(name, where(i) + ": normal is not finite " + str(n));
        double length = safeNorm(n);
        if (!(length > kZeroNormal)) {
            if (zero == ZeroNormal::Refused) fail(name, where(i) + ": normal is zero");
            n = Eigen::Vector3d::Zero();
            continue;
        }
        n = safeNormalized(n);
    }
}

// A mesh without normals (PLY, OFF): the vertices its polygons use, with area-weighted normals. A vertex no
// polygon uses is dropped; a non-finite one, or a used one whose polygons have no area, is an error naming it
// (`where(i)` names input vertex i).
template <class Where>
OrientedPoints meshPoints(const std::vector<Eigen::Vector3d>& positions, const Polygons& polygons,
                          const std::string& name, Where where) {
    for (size_t i = 0; i < positions.size(); ++i)
        if (!positions[i].allFinite()) fail(name, where(i) + ": coordinate is not finite " + str(positions[i]));
    std::vector<Eigen::Vector3d> sums(positions.size(), Eigen::Vector3d::Zero());
    std::vector<char> used(positions.size(), 0);
    addAreaNormals(positions, polygons, sums, used);
    double diagonal = usedDiagonal(positions, used);
    OrientedPoints out;
    std::vector<size_t> vertexOf;
    std::vector<uint32_t> renumber(positions.size(), kDropped);
    for (size_t i = 0; i < sums.size(); ++i) {
        if (!used[i]) continue;
        settleAreaNormal(sums[i], diagonal, name, [&] { return where(i); });
        renumber[i] = uint32_t(vertexOf.size());
        vertexOf.push_back(i);
        out.positions.push_back(positions[i]);
        out.normals.push_back(sums[i]);
    }
    finish(out, name, [&](size_t i) { return where(vertexOf[i]); });
    appendTriangles(polygons, renumber, 0, out.triangles);
    return out;
}

}  // namespace ink::io
