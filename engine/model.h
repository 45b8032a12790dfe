// From a file to a fitted HRBF: load, normalize (unit diagonal), merge duplicates, choose control points by
// farthest-point sampling, fit (ALGORITHM.md §1–2).
#pragma once

#include "hrbf.h"
#include "points.h"

#include <string>

namespace ink {

constexpr size_t kDefaultControlPoints = 1000;  // when the input has more points and none were asked for

struct ModelOptions {
    size_t controlPoints = 0;  // 0 = all input points up to kDefaultControlPoints
};

struct Model {
    Hrbf hrbf;
    FitStats fit;
    size_t inputPoints = 0;
    size_t mergedDuplicates = 0;
    double loadSeconds = 0;
};

// Refuses options no model can satisfy (--control-points above kMaxControlPoints) before any work is done.
void checkModelOptions(const ModelOptions& options);

// Fits points given in the input's units. Throws ink::Error for too few distinct points or absurd requests.
Model fitModel(OrientedPoints points, const ModelOptions& options);
// Loads a mesh or point file and fits it, or loads a fitted model from a .hrbf file (options.controlPoints
// is then ignored; fit holds the stats at the stored centres, with seconds = 0). Every error from the file
// or the fit names `path`.
Model loadModel(const std::string& path, const ModelOptions& options);

}  // namespace ink
