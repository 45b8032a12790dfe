// Atomic output: every file Inkwell writes goes to a temporary name first and is renamed when complete, so a
// failure never leaves a partial file behind.
#pragma once

#include <functional>
#include <string>

namespace ink {

// Calls write(tmpPath) and renames tmpPath to path; on any failure removes tmpPath and throws ink::Error.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write);

// Refuses, up front, an output path writeAtomically could not write (a missing or read-only directory, a
// directory in its place), with the one-line message the write would give: it creates and removes the
// temporary file. Does nothing for an empty path. Commands call it before their work, so that a typo in
// the output path costs no fit, and so that an output is not left behind by a later one failing.
void checkWritable(const std::string& path);

}  // namespace ink
