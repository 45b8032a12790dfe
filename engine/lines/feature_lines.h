// Feature lines of a mesh (docs/lines.md, Creases and boundaries): creases, where the faces on either side of an
// edge turn by more than the crease angle, and boundaries, the edges of one face (an open scan's rim, a hole).
// Chained into long polylines along the mesh's edges, each point kept within a few pixels of the fitted surface
// (the edge itself, beside the fit's rounding of it), so that the device decides what shows as for every other
// pen line. No Vulkan here.
#pragma once

#include "io/oriented_points.h"
#include "lines/lines.h"
#include "surface/support.h"
#include "surface/surface.h"

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

namespace ink {

// The crease angle: an edge whose two faces' normals turn by more than this is a crease. The same 60° at which
// the face sampling stops smoothing a vertex's normal across faces (surface_sampling.h): a box's edges (90°) and
// an octahedron's (70.5°) are creases, a mesh of a smooth shape at any usable resolution (the bunny, a torus of
// 24 × 12 quads: 30°) has none.
constexpr double kCreaseAngleDeg = 60.0;

struct FeatureLines {
    std::vector<PenStroke> creases, boundaries;  // normalized coordinates, within kLineOffset of f = 0
    bool empty() const { return creases.empty() && boundaries.empty(); }
};

struct FeatureOptions {
    double creaseAngleDeg = kCreaseAngleDeg;
    // Chains shorter than this (normalized units) are dropped: a lone sharp edge of a noisy scan, not a feature.
    double minLength = 0.03;
    // The lines are resampled at this spacing along the edges (as the contour's predictor step,
    // ContourOptions::step).
    double step = 0.003;
};

// The feature lines of `mesh` (normalized coordinates, welded: one vertex a position) on `surface`. Edges shared
// by more than two faces, and edges whose other face has no area, are neither. Each chain runs between vertices
// where the feature edges do not simply continue (an end, a corner where three creases meet) or closes on itself;
// a point that does not reach f = 0 within a few Newton steps, or moves farther than `step` getting there, breaks
// the line.
FeatureLines meshFeatures(const OrientedPoints& mesh, const Surface& surface, const FeatureOptions& options = {});

// Which of a mesh's sharp edges (vertex pairs, faces turning past the crease angle) its crease lines follow: those
// where the fit turns too (`agrees`, per edge: a coarse scan's stray sharp edges, where the fit is smooth, stay out),
// and a run of at most `maxRun` where it does not between two that do along the same chain: the same crease, where
// the fit rounds a thin face away (CGAL's turbine: its flange's 90° rim had three gaps of 40-50 pixels). In
// `sharp`'s order.
std::vector<std::array<uint32_t, 2>> creaseEdges(const std::vector<std::array<uint32_t, 2>>& sharp,
                                                 const std::vector<bool>& agrees, size_t maxRun);

// The parts of a mesh (triangles joined across edges of two faces) and which are open: a part with an edge of one
// face, or of three and more (a rim, a hole, a fin on a body). An open part is seen from both sides: its faces do
// not hide its creases, and its back is drawn (Model::twoSided). A triangle with a repeated vertex joins nothing and is
// its own closed part.
struct MeshParts {
    std::vector<uint32_t> part;  // a triangle's part: the index of one of its triangles
    std::vector<char> open;      // by part index
    bool anyOpen = false;
    bool openAt(size_t triangle) const { return open[part[triangle]] != 0; }
};
MeshParts meshParts(const OrientedPoints& mesh);

// The crease lines of a point cloud (normalized coordinates, oriented points without faces) on `surface`: where a
// point's 12 nearest neighbours' normals fall into two tight groups (each within ~18°) turning by more than the
// crease angle, with at most one normal between them (a smooth bend as sharp turns them through every angle;
// neighbours turned past 120° are the other side of a thin part, and left out), the edge is the line where the
// groups' planes meet. The points nearest it, one a cell of the point spacing, are chained along it (each links to the
// nearest ahead and behind, within three spacings and 30°, where the two choose each other), then smoothed and
// kept near the surface as a mesh's creases are; chains under minLength go. A smooth shape's normals turn by a
// few degrees between neighbours: no creases. Its boundaries: rimLines.
FeatureLines pointFeatures(const OrientedPoints& cloud, const Surface& surface, const FeatureOptions& options = {});

// The open rims of a point cloud (normalized coordinates, oriented points without faces; docs/lines.md, Open
// surfaces), as boundaries are a mesh's edges of one face: per point, the unit direction across its rim, out of the
// surface, in its tangent plane (zero where it is not on one). A point may stand on a rim where its neighbours
// within 1.5 of its reach leave a gap of over 90° (Support::across, as PCL's boundary estimation; the direction is the
// gap's bisector); it does where the surface does not go on that way: walked 1.6 of its reach across the gap along
// the surface (four steps, each projected onto f = 0, turning with it), the walk ends where the input does not hold
// it (`holds`: the support, and the far field's trim). A walk that loses the surface finds no rim. Round a crease,
// round a thin part (a horn's tip, where its normals turn) and across a closed scan's sparse rows, the surface goes on,
// and holds.
std::vector<Eigen::Vector3f> cloudRims(const OrientedPoints& cloud, const Surface& surface, const Support& support,
                                       const std::function<bool(const Eigen::Vector3d&)>& holds);

// A point cloud's boundary lines: its rim points (cloudRims) averaged one a cell of their spacing (a ragged rim has
// them in two rows), chained along the rim (within three spacings, the rim's direction within 60°, each along the
// other's within 70°: the shortest such links first, one ahead and one behind a sample), then smoothed and kept near
// the surface as a mesh's boundaries are; chains under minLength go.
// `samples` (when given) gets the lines' points with their way out of the surface, for Support::setRims.
std::vector<PenStroke> rimLines(const OrientedPoints& cloud, const std::vector<Eigen::Vector3f>& outward,
                                const Surface& surface, const Support& support, const FeatureOptions& options = {},
                                std::vector<Support::RimSample>* samples = nullptr);

// The contour laid onto the feature lines drawn beside it: a contour point within `radius` of a point of `lines`,
// on the same side (normals less than 90° apart) and running the same way (tangents within 30°), moves onto the
// nearest such point; a stretch left between such points that spans under `minRun` end to end is bridged straight;
// where the contour leaves a line it eases off over four points. The fit rounds a crease, and its contour along the
// rounded edge ripples with the fit beside the smoothed crease line that stands for the edge (the fandisk's
// outline, drawn twice, wobbled); snapped, it is drawn once, smooth, and with the contour's pen and visibility.
// `snapped` counts the points moved.
std::vector<PenStroke> snapToLines(const std::vector<PenStroke>& contours, const std::vector<PenStroke>& lines,
                                   double radius, double minRun, size_t* snapped = nullptr);

// The same with the lines' points indexed once (a grid of cells of `radius`), for a contour traced every view.
class LineSnap {
public:
    LineSnap() = default;
    LineSnap(const std::vector<PenStroke>& lines, double radius);
    std::vector<PenStroke> apply(const std::vector<PenStroke>& contours, double minRun,
                                 size_t* snapped = nullptr) const;

private:
    struct Entry {
        Eigen::Vector3f p, n, t;  // position, normal (a crease's: its faces' mean), unit tangent
    };
    uint64_t key(const Eigen::Vector3f& p, int dx, int dy, int dz) const;
    std::vector<Entry> entries_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
    double radius_ = 0, inverse_ = 0;
};

// Moves x onto f = 0 by Newton steps along ∇f and returns the unit normal there in `normal`; false when it does
// not converge or moves farther than `reach`.
bool projectToSurface(const Surface& surface, Eigen::Vector3d& x, Eigen::Vector3d& normal, double reach);

}  // namespace ink
