// Oriented points spread evenly over a mesh's triangles (issue 15), fitted besides the vertices so that the
// surface follows the faces and not only the corners: a low-poly mesh's long thin triangles (a spider's legs)
// otherwise have no point along their length, and the fit breaks them into beads.
#pragma once

#include "io/oriented_points.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ink {

// Vertices and face samples together stay under this, whatever the mesh (a dense mesh gets fewer samples, one
// with this many vertices none).
constexpr size_t kMaxSampledPoints = 100000;
// The spacing face samples aim at, in bounding-box diagonals: the 1% within which the drawing must follow the
// input surface (issue 15's "Done when").
constexpr double kFaceSpacing = 0.01;

// Each triangle's area, 0 for the degenerate ones: not finite, or below 1e-12 of the squared diagonal (the
// scale at which the readers call a vertex's area normal zero). Sampling and fidelity skip those.
std::vector<double> triangleAreas(const OrientedPoints& mesh);

// `count` oriented points on the triangles of `mesh` (the vertices are not included: callers append them).
// Area-weighted and stratified: systematic sampling along the triangles' cumulative area gives each triangle
// the floor or the ceiling of count · area / total; inside a triangle the points follow the R2 low-discrepancy
// sequence (Roberts 2018), rotated per triangle, mapped onto it by the square-root warp, and lifted onto the
// triangle's curved PN patch (Vlachos et al. 2001), with the patch's own normal there. The patch's corner normals
// are the area-weighted means of the faces around each corner that turn less than `creaseAngleDeg` (60°) from the
// triangle's (a crease splits them: the fit's --crease-angle, so that the edges drawn as crease lines stay sharp), so a
// CAD part's faces between creases stay flat; the vertex's own normal where it is within 20° of that mean and, beside a
// crease, lifts the patch by less than 0.5% of the diagonal; a flat face's sliver keeps its plane's normal where a
// leaning corner would lift it by more. The flat triangle and its face normal (turned to the side of the vertex
// normals) where the vertex normals cancel or the patch folds. Triangles of zero area (relative to the squared
// diagonal) get none. Deterministic: the same mesh, count and seed give the same points. Empty if the mesh has no
// triangle with area. O(count + T). `triangles`, when given, gets the triangle of each sample.
OrientedPoints sampleFaces(const OrientedPoints& mesh, size_t count, uint32_t seed,
                           std::vector<uint32_t>* triangles = nullptr, double creaseAngleDeg = 60.0);

// How many face samples a mesh needs: enough for a spacing of kFaceSpacing of the diagonal over the whole area,
// and for about one sample a spacing along every edge longer than that from the tallest triangle beside it (a
// strip of height h needs a density of 2/(h · spacing); heights below 1/8 of the spacing count as 1/8, so a
// needle cannot ask for millions). A sliver between well-shaped triangles asks for nothing: their samples fill
// its surroundings. Capped so that samples and vertices stay within kMaxSampledPoints. 0 for a mesh without
// triangles.
size_t faceSampleCount(const OrientedPoints& mesh);

}  // namespace ink
