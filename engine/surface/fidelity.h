// How closely a set of points (a drawing's refined points) follows a mesh, both ways (issue 15's "Done when"):
// coverage, the share of a dense sampling of the mesh's surface with a point within a tolerance, so holes and
// lost parts show; and accuracy, the share of the points within the tolerance of the surface, so stray sheets
// and blobs show. Everything in the mesh's own units; distances reported in bounding-box diagonals.
#pragma once

#include "io/oriented_points.h"

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ink {

struct Fidelity {
    double diagonal = 0;        // the mesh's bounding-box diagonal, in its units
    double tolerance = 0;       // in diagonals
    size_t surfaceSamples = 0;  // the dense sampling of the mesh
    size_t points = 0;
    // Surface → points: the distance from each surface sample to the nearest point.
    double coverage = 0;  // the share within the tolerance
    double coverageP99 = 0, coverageMax = 0;
    // Points → surface: the distance from each point to the nearest triangle.
    double accuracy = 0;  // the share within the tolerance
    double accuracyP99 = 0, accuracyMax = 0;
};

// The mesh must have triangles with area (a point format has none: an ink::Error says so). `tolerance` is in
// diagonals; `surfaceSamples` 0 picks a spacing of a quarter of the tolerance over the area (between 10⁴ and
// 10⁶ samples), on the triangles' curved patches (sampleFaces with `creaseAngleDeg`, the fit's --crease-angle:
// past it an edge stays sharp; the fit samples the mesh welded by position, this the triangles as given, so a file
// that repeats its vertices at seams has its corners split there). The sampling is deterministic. Cost: a k-d tree of
// the points (nanoflann) for the coverage, a uniform grid of the triangles for the accuracy; about a second for 10⁵
// points and 10⁵ triangles.
Fidelity measureFidelity(const OrientedPoints& mesh, const std::vector<Eigen::Vector3d>& points,
                         double tolerance = 0.01, size_t surfaceSamples = 0, double creaseAngleDeg = 60.0);

// The distance from each point to the nearest of the mesh's triangles with area (a uniform grid, searched ring
// by ring from the point's cell until no nearer triangle can remain). For the tests and measureFidelity.
std::vector<double> distancesToMesh(const OrientedPoints& mesh, const std::vector<Eigen::Vector3d>& points);

}  // namespace ink
