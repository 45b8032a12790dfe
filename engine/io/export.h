// Writing point sets: binary little-endian PLY with x y z in the input's units (float, or double when float
// cannot hold the positions to 1e-6 of the diagonal: far from the origin, or at extreme scales), float
// nx ny nz, the refinement level and the rank (PointRecord::tone: the point is in the prefix set of fraction t when
// rank < t).
#pragma once

#include "refine/point_record.h"
#include "surface/hrbf.h"

#include <string>
#include <vector>

namespace ink {

// Positions go through frame.toInput(); normals are unchanged (the frame is a uniform scale + translation).
void writePointsPly(const std::string& path, const std::vector<PointRecord>& points, const Frame& frame);

}  // namespace ink
