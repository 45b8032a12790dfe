// The .hrbf model file: a fitted HRBF saved so that it can be rendered again without fitting.
//
// A versioned text format (docs/hrbf-format.md): first line `inkwell-hrbf 1`, then `centers N`,
// `frame cx cy cz scale`, `linear ax ay az b`, N lines `x y z nx ny nz alpha bx by bz` and `end`.
// Numbers are written with 17 significant digits and read back exactly, so a round trip is bit-exact.
#pragma once

#include "hrbf.h"

#include <string>

namespace ink {

// Writes `model` to `path` atomically (a temporary file renamed into place). Throws ink::Error when the
// file cannot be written or the model is inconsistent (e.g. no normals).
void saveHrbf(const std::string& path, const Hrbf& model);

// Reads a .hrbf file. Throws ink::Error with one line naming the file, the line and the problem.
Hrbf loadHrbf(const std::string& path);

// The same on bytes already in memory (tests, fuzzers); `name` is used in messages.
Hrbf parseHrbf(const std::string& bytes, const std::string& name);

}  // namespace ink
