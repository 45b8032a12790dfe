// PNG files and atomic output: every file Inkwell writes goes to a temporary name first and is renamed
// when complete, so a failure never leaves a partial file behind.
#pragma once

#include "renderer.h"

#include <functional>
#include <string>

namespace ink {

// Calls write(tmpPath) and renames tmpPath to path; on any failure removes tmpPath and throws ink::Error.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write);

void writePng(const std::string& path, const RgbaImage& image);
RgbaImage readPng(const std::string& path);

}  // namespace ink
