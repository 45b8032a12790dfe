// Input geometry: oriented points loaded from meshes and point files, cleaned for fitting.
//
// Formats (see docs/file-formats.md):
//   .obj            v / vn / f, polygons, negative indices (tinyobjloader)
//   .ply            ascii, binary_little_endian, binary_big_endian; float or double x y z,
//                   optional nx ny nz, optional faces (vertex_indices / vertex_index lists)
//   .pts .xyzn .txt one oriented point per line: x y z nx ny nz; '#' starts a comment
// Meshes without normals get area-weighted vertex normals; vertices no face references are ignored.
// Every function here throws ink::Error with one line naming the file, the line or element, and the
// problem (NaN, zero normal, index out of range, truncated body, absurd element count, ...).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ink {

struct OrientedPoints {
    std::vector<Eigen::Vector3d> positions;
    std::vector<Eigen::Vector3d> normals;  // unit length, one per position
};

// Picks the loader by extension (case-insensitive). Normals are normalized; a zero or non-finite
// normal, or a non-finite coordinate, is an error naming where it is.
OrientedPoints loadPoints(const std::string& path);

// The same loaders on bytes already in memory (used by tests and fuzzers); `name` is used in messages,
// `format` is "obj", "ply" or "pts".
OrientedPoints parsePoints(const std::string& bytes, const std::string& format, const std::string& name);

// Merges points closer than `tolerance` (absolute, in the points' units; callers pass ~1e-9 of the
// bounding-box diagonal), keeping the first of each cluster. Returns how many were merged.
size_t mergeDuplicates(OrientedPoints& points, double tolerance);

// Deterministic farthest-point sampling: starts at the point with the smallest (x, y, z) in
// lexicographic order, then repeatedly takes the point farthest from those chosen (ties: lowest index).
// Returns indices into `positions`; count >= positions.size() returns all of them in input order.
std::vector<size_t> farthestPointSample(const std::vector<Eigen::Vector3d>& positions, size_t count);

}  // namespace ink
