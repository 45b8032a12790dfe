// The .hrbf model file: a fitted HRBF saved so that it can be rendered again without fitting.
//
// A versioned text format (docs/hrbf-format.md): `inkwell-hrbf 1` holds the global fit (`centers N`,
// `frame cx cy cz scale`, `linear ax ay az b`, N lines `x y z nx ny nz alpha bx by bz`, `end`); `inkwell-hrbf 2`
// the partition of unity (its far field, patches, nodes and points). Numbers are written with 17 significant
// digits and read back exactly, so a round trip is bit-exact.
#pragma once

#include "surface.h"

#include <string>

namespace ink {

// Writes `model` to `path` atomically (a temporary file renamed into place). Throws ink::Error when the
// file cannot be written or the model is inconsistent (e.g. no normals).
void saveHrbf(const std::string& path, const Surface& model);

// Reads a .hrbf file. Throws ink::Error with one line naming the file, the line and the problem.
Surface loadHrbf(const std::string& path);

// The same on bytes already in memory (tests, fuzzers); `name` is used in messages.
Surface parseHrbf(const std::string& bytes, const std::string& name);

}  // namespace ink
