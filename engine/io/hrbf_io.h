// The .hrbf model file: a fitted HRBF saved so that it can be rendered again without fitting.
//
// Versioned (docs/hrbf-format.md). Version 3, the default, is binary: a 128-byte little-endian header with a
// CRC-32C of the whole file, then 64-byte aligned arrays (the global fit and the far field in double; the
// partition of unity's patches, nodes and points in float, as the device evaluates them; the refinement seeds).
// Versions 1 (`inkwell-hrbf 1`, the global fit) and 2 (`inkwell-hrbf 2`, the partition of unity) are text, for
// interchange: numbers with 17 significant digits, read back exactly. The reader tells them apart by content.
#pragma once

#include "surface/surface.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ink {

// The largest .hrbf file read: a global model is at most ~1 MB (4000 lines of ten numbers), a partition of unity
// of 10⁶ points some hundreds of MB (the bunny with its face samples, 18,210 points, is 18.8 MB). Larger files
// are refused unread. docs/hrbf-format.md and docs/robustness.md quote it.
constexpr size_t kMaxHrbfBytes = size_t(1) << 30;  // 1 GiB

// Binary (version 3) or text (version 1 for the global fit, 2 for the partition of unity).
enum class HrbfFormat { Binary, Text };

// Writes `model` to `path` atomically (a temporary file renamed into place). Throws ink::Error when the
// file cannot be written or the model is inconsistent (e.g. no normals). Version 3 stores the partition of unity
// in float: the model loaded back is the one the device draws (its float evaluation is the same bit for bit),
// and saving that again gives the same bytes.
void saveHrbf(const std::string& path, const Surface& model, HrbfFormat format = HrbfFormat::Binary);

// The bytes saveHrbf writes.
std::string encodeHrbf(const Surface& model, HrbfFormat format);

// Reads a .hrbf file of any version. Throws ink::Error with one line naming the file, the line or array where
// there is one, and the problem. `measured`, when given, receives measureFit(model) (the reader evaluates the
// model at its centres anyway).
Surface loadHrbf(const std::string& path, FitStats* measured = nullptr);

// The same on bytes already in memory (tests, fuzzers); `name` is used in messages.
Surface parseHrbf(const std::string& bytes, const std::string& name, FitStats* measured = nullptr);

// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78; crc32c("123456789") = 0xE3069283) of `bytes`, continuing
// from `crc` (0 to start): version 3's checksum (docs/hrbf-format.md).
uint32_t crc32c(std::string_view bytes, uint32_t crc = 0);

// Version 3's header: where the checksum is, and its magic bytes.
constexpr size_t kHrbf3ChecksumOffset = 24;
constexpr std::string_view kHrbf3Magic{"\x89HRBF\r\n\x1a", 8};

}  // namespace ink
