// What every point-loader fuzz target does: parse the input as one format, accept ink::Error as the
// loader's answer to bad input, and check what a successful parse promises (docs/file-formats.md). Any
// other exception, a crash, a sanitizer report, a hang or a huge allocation is a finding.
#pragma once

#include "base/common.h"
#include "io/points.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace fuzz {

[[noreturn]] inline void broken(const char* what) {
    std::fprintf(stderr, "fuzz: a parse succeeded but broke its promise: %s\n", what);
    std::abort();
}

// Runs `parse` on the input and checks the outcome as above.
template <class Parse>
int parseOnce(const uint8_t* data, size_t size, Parse parse) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    ink::OrientedPoints p;
    try {
        p = parse(bytes);
    } catch (const ink::Error& e) {
        // One line: the apps print it as "inkwell: <message>".
        std::string message = e.what();
        if (message.empty() || message.find('\n') != std::string::npos) broken("an error message is not one line");
        return 0;
    }
    if (p.positions.empty()) broken("no points");
    if (p.positions.size() != p.normals.size()) broken("positions and normals differ in number");
    for (size_t i = 0; i < p.positions.size(); ++i) {
        if (!p.positions[i].allFinite()) broken("a coordinate is not finite");
        // Unit length; or zero in a point cloud (none in the file, or 0 0 0: the fit estimates it).
        const bool cloudZero = p.triangles.empty() && p.normals[i] == Eigen::Vector3d::Zero();
        if (!p.normals[i].allFinite() || (std::abs(p.normals[i].norm() - 1.0) > 1e-9 && !cloudZero))
            broken("a normal is neither of unit length nor a point cloud's zero");
    }
    return 0;
}

inline int parsePointsOnce(const uint8_t* data, size_t size, const char* format) {
    return parseOnce(data, size, [format](const std::string& bytes) {
        return ink::parsePoints(bytes, format, std::string("fuzz.") + format);
    });
}

}  // namespace fuzz
