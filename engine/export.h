// Writing point sets: binary little-endian PLY with float x y z nx ny nz in the input's units, the refinement
// level and the rank (PointRecord::tone: the point is in the prefix set of fraction t when rank < t).
#pragma once

#include "hrbf.h"
#include "point_record.h"

#include <string>
#include <vector>

namespace ink {

// Positions go through frame.toInput(); normals are unchanged (the frame is a uniform scale + translation).
void writePointsPly(const std::string& path, const std::vector<PointRecord>& points, const Frame& frame);

}  // namespace ink
