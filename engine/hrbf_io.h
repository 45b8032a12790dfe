// The .hrbf model file: a fitted HRBF saved so that it can be rendered again without fitting.
//
// A versioned text format (docs/hrbf-format.md): `inkwell-hrbf 1` holds the global fit (`centers N`,
// `frame cx cy cz scale`, `linear ax ay az b`, N lines `x y z nx ny nz alpha bx by bz`, `end`); `inkwell-hrbf 2`
// the partition of unity (its far field, patches, nodes and points). Numbers are written with 17 significant
// digits and read back exactly, so a round trip is bit-exact.
#pragma once

#include "surface.h"

#include <cstddef>
#include <string>

namespace ink {

// The largest .hrbf file read: a global model is at most ~1 MB (4000 lines of ten numbers), a partition of unity
// of 10⁶ points some hundreds of MB (the bunny with its face samples, 18,210 points, is 18.8 MB). Larger files
// are refused unread. docs/hrbf-format.md and docs/robustness.md quote it.
constexpr size_t kMaxHrbfBytes = size_t(1) << 30;  // 1 GiB
// The most nodes a patch of a loaded partition of unity may hold: a fit makes 8 to 24 (PuOptions::minPatch,
// maxPatch); every evaluation near a patch visits all of them, so a 65,000-node patch took 78 s to render.
constexpr size_t kMaxPatchNodes = 1024;

// Writes `model` to `path` atomically (a temporary file renamed into place). Throws ink::Error when the
// file cannot be written or the model is inconsistent (e.g. no normals).
void saveHrbf(const std::string& path, const Surface& model);

// Reads a .hrbf file. Throws ink::Error with one line naming the file, the line and the problem.
Surface loadHrbf(const std::string& path);

// The same on bytes already in memory (tests, fuzzers); `name` is used in messages.
Surface parseHrbf(const std::string& bytes, const std::string& name);

}  // namespace ink
