// Cleaning oriented points before a fit: merging duplicates and picking well-spread control points.
#pragma once

#include "io/oriented_points.h"

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ink {

// Merges points closer than `tolerance` (absolute, in the points' units; callers pass ~1e-9 of the
// bounding-box diagonal), keeping the first of each cluster. Returns how many were merged.
// Both merges renumber the triangles; a triangle that loses a corner, or two corners to one point, is dropped.
size_t mergeDuplicates(OrientedPoints& points, double tolerance);

// Points closer than `tolerance` but not equal make the fit ill-conditioned: two nearly equal rows of the
// system with different normal constraints (a mesh's split vertices at a crease, a seam). Each cluster of
// such points becomes its first point with the cluster's mean normal; a cluster whose normals cancel (the
// mean shorter than ½: the two sides of a sheet at one place) is dropped. Grid-based: any number of points.
struct NearMerge {
    size_t merged = 0;   // points folded into another
    size_t dropped = 0;  // points of clusters whose normals cancel
};
NearMerge mergeNearPoints(OrientedPoints& points, double tolerance);

// Deterministic farthest-point sampling: starts at the point with the smallest (x, y, z) in
// lexicographic order, then repeatedly takes the point farthest from those chosen (ties: lowest index).
// Returns indices into `positions`; count >= positions.size() returns all of them in input order.
std::vector<size_t> farthestPointSample(const std::vector<Eigen::Vector3d>& positions, size_t count);

}  // namespace ink
