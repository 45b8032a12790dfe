// Cleaning oriented points before a fit: merging duplicates and picking well-spread control points.
#pragma once

#include "oriented_points.h"

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ink {

// Merges points closer than `tolerance` (absolute, in the points' units; callers pass ~1e-9 of the
// bounding-box diagonal), keeping the first of each cluster. Returns how many were merged.
size_t mergeDuplicates(OrientedPoints& points, double tolerance);

// Deterministic farthest-point sampling: starts at the point with the smallest (x, y, z) in
// lexicographic order, then repeatedly takes the point farthest from those chosen (ties: lowest index).
// Returns indices into `positions`; count >= positions.size() returns all of them in input order.
std::vector<size_t> farthestPointSample(const std::vector<Eigen::Vector3d>& positions, size_t count);

}  // namespace ink
