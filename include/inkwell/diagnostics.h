// The library's own checks and benchmarks, run inside it (white box: they read the refinement's counters, trace
// the contour on the device and time the CPU reference beside it), so that a program on the public API — the
// command line's `validate` and `bench` — can run them on any device.
#pragma once

#include "inkwell/inkwell.h"

#include <cstdint>
#include <string>
#include <vector>

namespace inkwell {

// ---- Self-check (`inkwell validate`) -------------------------------------------------------------------

// One model's check: each style refined (3 levels), its points and stipples read back, the contour traced on the
// device where it can be, and an image rendered; every invariant a user relies on that failed, in a line each.
struct SelfCheck {
    std::string scene;                  // "sphere", "torus", or the model's path
    size_t points = 0;                  // refined points checked
    std::vector<std::string> failures;  // empty: all held
};

// Checks a sphere and a torus fitted to built-in points, and `model` too when it is not empty (fitted with
// `options`). Run it on a Device made with DeviceOptions::validation, and read its validationErrors() after:
// a check that passes with validation messages has failed.
std::vector<SelfCheck> selfCheck(Device& device, const std::string& model = {}, const ModelOptions& options = {},
                                 const Reporter& reporter = {});

// ---- Benchmarks (`inkwell bench`) ---------------------------------------------------------------------

struct BenchWorkload {
    enum class Source {
        File,       // `model`
        Sphere,     // six oriented points on the axes (the report's smallest)
        Torus100k,  // 10⁵ oriented points on a torus
    };
    std::string name;
    Source source = Source::File;
    std::string model;
    size_t controlPoints = 0;  // 0: as the fit chooses
    uint32_t levels = 4;
    FitMethod method = FitMethod::PartitionOfUnity;
    // Pen lines: contours and hatching over the stipple set's depth, no dots (docs/lines.md); traced and solved on
    // the device, or on the CPU.
    bool lines = false;
    bool linesOnDevice = false;
};

struct BenchOptions {
    uint32_t frames = 30;  // frames timed, the camera orbiting, after three untimed
    Distribution distribution = Distribution::BlueNoise;
    bool screenSpacing = true;
};

// Times one run of `workload` end to end: load and fit, refine and select (and the CPU reference's refinement
// beside it), the first view's contour, the renderer, then `frames` frames of 1024². Returns the figures as one
// JSON object (docs/performance.md names its fields: fit_seconds, refine_seconds, preprocess_ms, frame_ms_median,
// select_ms, cpu_refine_seconds, page, ...).
std::string bench(Device& device, const BenchWorkload& workload, const BenchOptions& options = {},
                  const Reporter& reporter = {});

}  // namespace inkwell
