// Input geometry: oriented points loaded from meshes and point files (the readers are in io/, one file per
// format), cleaned for fitting (clean.h, included here).
//
// Formats (see docs/file-formats.md):
//   .obj            v / vn / f, polygons, negative indices
//   .ply            ascii, binary_little_endian, binary_big_endian; float or double x y z,
//                   optional nx ny nz, optional faces (vertex_indices / vertex_index lists)
//   .pts .xyzn .txt one point per line: x y z nx ny nz, or x y z on every line; '#' starts a comment
//   .xyz .pwn       the same, with an optional first line holding the number of points
//   .off            OFF, COFF, NOFF, CNOFF (normals used), polygons
//   .stl            ascii and binary; corners welded, normals from the winding
//   .gltf .glb      glTF 2.0: the default scene's triangle meshes, node transforms applied
// Meshes without normals get area-weighted vertex normals, as do a mesh's vertices whose normal the file gives as
// zero; vertices no face references are ignored.
// Every function here throws ink::Error with one line naming the file, the line or element, and the
// problem (NaN, zero normal, index out of range, truncated body, absurd element count, ...).
#pragma once

#include "io/oriented_points.h"
#include "surface/clean.h"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ink {

// Picks the loader by extension (case-insensitive). Normals are normalized; a point cloud's missing or zero ones are
// zero (the fit estimates them); a non-finite normal, a mesh's zero one that no faces can replace, or a non-finite
// coordinate, is an error naming where it is.
OrientedPoints loadPoints(const std::string& path);

// The same loaders on bytes already in memory (used by tests and fuzzers); `name` is used in messages,
// `format` is "obj", "ply", "pts", "xyz", "off", "stl", "gltf" or "glb".
OrientedPoints parsePoints(const std::string& bytes, const std::string& format, const std::string& name);

}  // namespace ink
