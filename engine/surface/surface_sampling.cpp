// Face sampling (surface_sampling.h): systematic area-weighted allocation, R2 points inside each triangle.
#include "surface/surface_sampling.h"

#include "base/random.h"
#include "base/triangle.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <unordered_map>

namespace ink {

using Eigen::Vector3d;

namespace {

// The bounding-box diagonal of the positions.
double diagonalOf(const std::vector<Vector3d>& positions) {
    if (positions.empty()) return 0;
    Vector3d lo = positions.front(), hi = lo;
    for (const Vector3d& p : positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return (hi - lo).norm();
}

double unit(uint32_t bits) { return double(bits) * (1.0 / 4294967296.0); }

// The curved PN triangle (Vlachos et al. 2001) over a mesh triangle: the cubic Bézier patch through the corners,
// tangent there to the corners' normals, each edge's curve depending on that edge's two corners alone (neighbouring
// patches share their edges). A point on the flat triangle carries a normal that the flat triangle does not have:
// fitted together, the two make the surface ripple between the vertices at the triangle's scale (a 2,048-vertex
// torus: 21,906 contour cusps with all its samples flat, 6 with all of them on their patches). A sample takes the
// patch's own normal, which agrees with its position; PN's separate quadratic normal field, made for shading, does not,
// and rippled the bunny's ears.
struct PnTriangle {
    Vector3d b[10];  // b300 b030 b003 b210 b120 b021 b012 b102 b201 b111

    PnTriangle(const Vector3d& p0, const Vector3d& p1, const Vector3d& p2, const Vector3d& n0, const Vector3d& n1,
               const Vector3d& n2) {
        auto edge = [](const Vector3d& pi, const Vector3d& pj, const Vector3d& ni) {
            return (2 * pi + pj - (pj - pi).dot(ni) * ni) / 3;
        };
        b[0] = p0, b[1] = p1, b[2] = p2;
        b[3] = edge(p0, p1, n0), b[4] = edge(p1, p0, n1);
        b[5] = edge(p1, p2, n1), b[6] = edge(p2, p1, n2);
        b[7] = edge(p2, p0, n2), b[8] = edge(p0, p2, n0);
        const Vector3d e = (b[3] + b[4] + b[5] + b[6] + b[7] + b[8]) / 6, v = (p0 + p1 + p2) / 3;
        b[9] = e + (e - v) / 2;
    }

    // The point at barycentrics (u, v, w) (u at p0) and the patch's normal there, ∂p/∂v' × ∂p/∂w' (unnormalized).
    Vector3d at(double u, double v, double w, Vector3d& normal) const {
        // p = Σ 3!/(i! j! k!) uⁱ vʲ wᵏ b_ijk; its partial derivatives in u, v, w as independent variables.
        const Vector3d du = 3 * u * u * b[0] + 6 * u * v * b[3] + 3 * v * v * b[4] + 3 * w * w * b[7] +
                            6 * u * w * b[8] + 6 * v * w * b[9];
        const Vector3d dv = 3 * v * v * b[1] + 3 * u * u * b[3] + 6 * u * v * b[4] + 6 * v * w * b[5] +
                            3 * w * w * b[6] + 6 * u * w * b[9];
        const Vector3d dw = 3 * w * w * b[2] + 3 * v * v * b[5] + 6 * v * w * b[6] + 6 * u * w * b[7] +
                            3 * u * u * b[8] + 6 * u * v * b[9];
        normal = (dv - du).cross(dw - du);  // along the triangle's plane u + v + w = 1
        return u * u * u * b[0] + v * v * v * b[1] + w * w * w * b[2] + 3 * u * u * v * b[3] + 3 * u * v * v * b[4] +
               3 * v * v * w * b[5] + 3 * v * w * w * b[6] + 3 * u * w * w * b[7] + 3 * u * u * w * b[8] +
               6 * u * v * w * b[9];
    }
};

// A corner's normal for the PN patch of one triangle: the area-weighted mean of the normals of the triangles around
// the vertex that turn less than the crease angle from it (60°, or the fit's --crease-angle: the edges drawn as
// crease lines stay sharp in the surface). A crease (a box's edge, 90°; an octahedron's, 70.5°) splits the vertex's
// normal, and a face between creases stays flat; the vertex normal (the mean across the crease) would bulge it, and
// a threshold on that normal's angle to the face cannot tell a box's corner (54.7°) from the rough corners of a
// decimated scan (the bunny's reach 50°). A low-poly CAD part whose faces meet at 30–60° (CGAL's tripod.off, 24
// vertices) is rounded at the default, its big faces curved up to 2.6% of the diagonal off the mesh
// (`sample --fidelity`: 93.77% of the points within 1%), and with --crease-angle 25 follows its faces (100%).
const double kOwnCos = std::cos(20.0 * M_PI / 180.0);
// Beside a crease the vertex's own normal leans across it, and the PN edge from the corner bulges off the face's
// plane by about 0.15 · length · sin(lean) (the cubic's control point lifted by length · sin(lean) / 3, 4/9 of that
// at a third of the way): past this fraction of the diagonal, half the 1% within which a drawing must follow its
// input, the corner takes the face's side. A plate's hole rim leans 19.6° (its long top triangles outweigh the
// wall's short ones) and bulged its top triangles by 1.7% of the diagonal, a ridge along each drawn as contour
// lenses on the flat face. A scan's rough vertices lean 3–15° across a fold of one face over 60° on edges of a few
// percent, and stay as they were (at 0.1% instead, the bunny's fit changed and with it its default view).
constexpr double kCornerBulge = 0.005;
// Triangles whose normals turn less than this from each other lie in one plane (a CAD part's flat face).
const double kFlatCos = std::cos(2.0 * M_PI / 180.0);
// A triangle whose longest edge is this many times its height over that edge is a sliver.
constexpr double kSliver = 6.0;

// Each triangle's unit normal, turned to the side of its vertex normals (0 for a degenerate one), and its area.
struct Faces {
    std::vector<Vector3d> normal;
    std::vector<uint32_t> start, list;  // the triangles around each vertex: list[start[v], start[v + 1])

    double diagonal;
    double creaseCos;  // faces around a corner that turn more than the crease angle from a triangle split it

    Faces(const OrientedPoints& mesh, const std::vector<double>& areas, double creaseAngleDeg)
        : normal(mesh.triangles.size()),
          diagonal(diagonalOf(mesh.positions)),
          creaseCos(std::cos(creaseAngleDeg * M_PI / 180.0)) {
        start.assign(mesh.positions.size() + 1, 0);
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Triangle& tri = mesh.triangles[t];
            Vector3d n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                             .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
            if (n.dot(mesh.normals[tri[0]] + mesh.normals[tri[1]] + mesh.normals[tri[2]]) < 0) n = -n;
            normal[t] = areas[t] > 0 ? Vector3d(n.normalized()) : Vector3d::Zero();
            for (uint32_t v : tri) ++start[v + 1];
        }
        for (size_t v = 0; v < mesh.positions.size(); ++v) start[v + 1] += start[v];
        list.resize(start.back());
        std::vector<uint32_t> at(start.begin(), start.end() - 1);
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
            for (uint32_t v : mesh.triangles[t]) list[at[v]++] = uint32_t(t);
    }

    // The normal of corner v of triangle t: the vertex's own (a file's, or the area-weighted mean) where it is
    // within 20° of the mean of the faces of t's smoothing group around v, and, where a crease passes v (a face
    // around it turns more than the crease angle from t), its lean across it bulges t's patch by less than
    // kCornerBulge; that mean where not. Then the sliver rule below.
    Vector3d corner(const OrientedPoints& mesh, uint32_t v, size_t t, const std::vector<double>& areas) const {
        Vector3d sum = Vector3d::Zero();
        bool crease = false;
        for (uint32_t k = start[v]; k < start[v + 1]; ++k) {
            if (normal[list[k]].dot(normal[t]) >= creaseCos)
                sum += areas[list[k]] * normal[list[k]];
            else
                crease = crease || areas[list[k]] > 0;
        }
        const double length = sum.norm();
        const Vector3d group = length > 0 ? Vector3d(sum / length) : normal[t];
        const Vector3d& own = mesh.normals[v];
        Vector3d chosen = group;
        if (own.dot(group) >= kOwnCos * own.norm()) {
            const Vector3d unit = own.normalized();
            double edge = 0;  // the longest edge from v
            for (uint32_t w : mesh.triangles[t]) edge = std::max(edge, (mesh.positions[w] - mesh.positions[v]).norm());
            if (!crease || !(0.15 * edge * unit.cross(group).norm() > kCornerBulge * diagonal)) chosen = unit;
        }
        // A flat face's sliver beside a fillet or a chamfer under the crease angle: the smoothing group's mean
        // leans towards it along the sliver, and a CAD face's fan of long thin triangles bulged by up to 2.9% of the
        // diagonal (CGAL's anchor.off). Where t is a sliver (its longest edge kSliver times its height over it) in a
        // flat region (another triangle at one of its corners lies in its plane) and the corner's normal leans
        // along it so far that it lifts the sliver's length by more than kCornerBulge (0.15 · length · the
        // normal's component along the sliver's axis, the median to its shortest edge), the corner takes the
        // plane's normal. Well-shaped triangles keep their patches (a UV sphere's quads are planar and would
        // turn into facets), and so do slivers whose normals lean across them (a coarse cylinder's long sides).
        const Triangle& tri = mesh.triangles[t];
        double longest2 = 0, shortest2 = INFINITY;
        int shortest = 0;
        for (int e = 0; e < 3; ++e) {
            const double l2 = (mesh.positions[tri[e]] - mesh.positions[tri[(e + 1) % 3]]).squaredNorm();
            longest2 = std::max(longest2, l2);
            if (l2 < shortest2) shortest2 = l2, shortest = e;
        }
        if (!(areas[t] > 0) || !(longest2 > kSliver * 2 * areas[t])) return chosen;
        const Vector3d axis = 0.5 * (mesh.positions[tri[shortest]] + mesh.positions[tri[(shortest + 1) % 3]]) -
                              mesh.positions[tri[(shortest + 2) % 3]];
        if (!(0.15 * std::abs(axis.dot(chosen)) > kCornerBulge * diagonal)) return chosen;
        bool coplanar = false;
        for (uint32_t u : tri)
            for (uint32_t k = start[u]; k < start[u + 1] && !coplanar; ++k)
                coplanar = list[k] != t && areas[list[k]] > 0 && normal[list[k]].dot(normal[t]) >= kFlatCos;
        return coplanar ? normal[t] : chosen;
    }
};

}  // namespace

std::vector<double> triangleAreas(const OrientedPoints& mesh) {
    const double d = diagonalOf(mesh.positions);
    std::vector<double> areas(mesh.triangles.size(), 0.0);
    for (size_t t = 0; t < areas.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vector3d& p0 = mesh.positions[tri[0]];
        double a = 0.5 * (mesh.positions[tri[1]] - p0).cross(mesh.positions[tri[2]] - p0).norm();
        areas[t] = std::isfinite(a) && a / d / d > 0.5e-12 ? a : 0.0;
    }
    return areas;
}

OrientedPoints sampleFaces(const OrientedPoints& mesh, size_t count, uint32_t seed, std::vector<uint32_t>* triangles,
                           double creaseAngleDeg) {
    if (triangles) triangles->clear();
    OrientedPoints out;
    const std::vector<double> areas = triangleAreas(mesh);
    double total = 0;
    for (double a : areas) total += a;
    if (count == 0 || !(total > 0)) return out;
    out.positions.reserve(count);
    out.normals.reserve(count);

    const Faces faces(mesh, areas, creaseAngleDeg);

    // Systematic sampling: sample k sits at (k + u) / count of the cumulative area; triangle t takes those that
    // fall in its stretch, the floor or the ceiling of its share.
    const double u = unit(pcg4d({seed, 0x5eed, 0, 0})[0]);
    const double step = total / double(count);
    // R2: the additive recurrence of the plastic number φ₂ (x³ = x + 1), a 2D low-discrepancy sequence.
    constexpr double kPhi2 = 1.32471795724474602596;
    constexpr double kA1 = 1.0 / kPhi2, kA2 = 1.0 / (kPhi2 * kPhi2);
    size_t last = areas.size() - 1;
    while (areas[last] == 0) --last;
    double start = 0;  // cumulative area before triangle t
    size_t k = 0;
    for (size_t t = 0; t <= last; ++t) {
        const double end = start + areas[t];
        const size_t first = k;
        // The last triangle with area takes whatever rounding left over.
        while (k < count && ((double(k) + u) * step < end || t == last)) ++k;
        const size_t here = k - first;
        if (here > 0) {
            const Triangle& tri = mesh.triangles[t];
            const Vector3d &p0 = mesh.positions[tri[0]], &p1 = mesh.positions[tri[1]], &p2 = mesh.positions[tri[2]];
            const Vector3d &n0 = mesh.normals[tri[0]], &n1 = mesh.normals[tri[1]], &n2 = mesh.normals[tri[2]];
            Vector3d face = (p1 - p0).cross(p2 - p0).normalized();
            if (face.dot(n0 + n1 + n2) < 0) face = -face;
            const PnTriangle pn(p0, p1, p2, faces.corner(mesh, tri[0], t, areas), faces.corner(mesh, tri[1], t, areas),
                                faces.corner(mesh, tri[2], t, areas));
            // Cranley–Patterson rotation of the sequence, per triangle, from the seed.
            auto r = pcg4d({seed, uint32_t(t), uint32_t(uint64_t(t) >> 32), 0x7a1});
            const double r1 = unit(r[0]), r2 = unit(r[1]);
            for (size_t j = 0; j < here; ++j) {
                double x = r1 + kA1 * double(j), y = r2 + kA2 * double(j);
                x -= std::floor(x);
                y -= std::floor(y);
                // Square-root warp: uniform on the triangle for uniform (x, y).
                const double sx = std::sqrt(x);
                const double b0 = 1 - sx, b1 = sx * (1 - y), b2 = sx * y;
                Vector3d n = b0 * n0 + b1 * n1 + b2 * n2, patchNormal;
                const double length = n.norm();
                const Vector3d onPatch = pn.at(b0, b1, b2, patchNormal);
                const double pl = patchNormal.norm();
                // On the flat triangle with its face's normal where the vertex normals (nearly) cancel, saying
                // nothing about the direction, or where the patch folds (its normal over 60° from theirs: a
                // sliver between disagreeing normals).
                if (triangles) triangles->push_back(uint32_t(t));
                if (length > 1e-2 && pl > 0 && patchNormal.dot(n) > 0.5 * pl * length && onPatch.allFinite()) {
                    out.positions.push_back(onPatch);
                    out.normals.push_back(patchNormal / pl);
                } else {
                    out.positions.push_back(b0 * p0 + b1 * p1 + b2 * p2);
                    out.normals.push_back(face);
                }
            }
        }
        start = end;
    }
    return out;
}

size_t faceSampleCount(const OrientedPoints& mesh) {
    const std::vector<double> areas = triangleAreas(mesh);
    const double spacing = kFaceSpacing * diagonalOf(mesh.positions);
    double total = 0;
    for (double a : areas) total += a;
    if (!(total > 0) || !(spacing > 0)) return 0;
    double wanted = total / (spacing * spacing);
    // Each edge longer than the spacing, with the tallest of its triangles over it: samples spread along an edge
    // from a triangle of height h over it, count · (area / total) of them over its length, come a spacing apart
    // when count = 2 · total / (h · spacing). The tallest triangle is the one that fills the edge's surroundings:
    // a sliver beside a well-shaped neighbour asks for nothing, a strip of slivers (a thin leg) does.
    std::unordered_map<uint64_t, double> tallest;
    for (size_t t = 0; t < areas.size(); ++t) {
        if (areas[t] == 0) continue;
        const Triangle& tri = mesh.triangles[t];
        for (size_t e = 0; e < 3; ++e) {
            const uint32_t a = tri[e], b = tri[(e + 1) % 3];
            const double length = (mesh.positions[a] - mesh.positions[b]).norm();
            if (length < spacing) continue;  // its ends are within a spacing of all of it
            double& h = tallest[edgeKey(a, b)];
            h = std::max(h, 2 * areas[t] / length);
        }
    }
    for (const auto& [edge, height] : tallest)
        wanted = std::max(wanted, total * 2 / (std::max(height, spacing / 8) * spacing));
    const size_t room = mesh.positions.size() < kMaxSampledPoints ? kMaxSampledPoints - mesh.positions.size() : 0;
    return std::min(room, size_t(std::ceil(std::min(wanted, double(kMaxSampledPoints)))));
}

}  // namespace ink
