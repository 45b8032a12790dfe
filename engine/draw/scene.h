// A model and its point sets on one device: what `render`, `capture` and the viewer draw, and what an
// embedding application keeps between frames.
#pragma once

#include "draw/camera.h"
#include "lines/contour_device.h"
#include "lines/feature_lines.h"
#include "lines/hatching.h"
#include "lines/lines.h"
#include "lines/strokes.h"
#include "refine/refine.h"
#include "surface/model.h"

#include <memory>
#include <vector>

namespace ink {

// Stipples, hatch-like lines of dots (direction sampling), or both sets drawn together.
enum class DrawStyle { Stipple, Direction, Both };
const char* drawStyleName(DrawStyle style);  // "stipple", "direction", "both"

// Pen lines to trace besides the point sets (docs/lines.md).
struct LineOptions {
    bool contours = false;  // the occluding contour, traced for each view (traceContours)
    bool hatching = false;  // hatching strokes, traced once for the model
    // A mesh's crease and boundary lines (Model::features, docs/lines.md), where it has them.
    bool creases = false, boundaries = false;
    // Where the contour is traced: on the device (DeviceContours) or the CPU (traceContours). Auto: on the device
    // where it is a GPU and the fit a partition of unity (docs/lines.md); on a CPU driver (lavapipe) the CPU's
    // tracer is the faster.
    enum class ContourTracer { Auto, Cpu, Device } contourTracer = ContourTracer::Auto;
    // Where the hatching's cross field is solved: on the device (cross_field_device.h) or the CPU, its twin
    // (solveCrossField). Auto: on the device where it is a GPU and the fit a partition of unity; on a CPU driver
    // (lavapipe) the CPU's solve is the faster (docs/lines.md).
    enum class FieldSolver { Auto, Cpu, Device } fieldSolver = FieldSolver::Auto;
    ContourOptions contour;
    HatchOptions hatch;
    bool any() const { return contours || hatching || creases || boundaries; }
};

class Scene {
public:
    // Refines the model for the style: one submission a set, waited for, its points the input does not support
    // dropped (Model::support); then traces the hatching.
    Scene(Context& ctx, Model model, DrawStyle style, const RefineOptions& options, const LineOptions& lines = {});
    // The same over a model shared with others (the public API's: a large scan's fit is not copied).
    Scene(Context& ctx, std::shared_ptr<const Model> model, DrawStyle style, const RefineOptions& options,
          const LineOptions& lines = {});
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // Replaces the point sets (new levels, another style); waits for the device to be idle first, since a
    // frame in flight may still read the old ones.
    void refine(DrawStyle style, const RefineOptions& options, const LineOptions& lines = {});
    // refine() in two halves, for a viewer that stays responsive while new sets are made: build makes and runs
    // the sets for a style without touching the current ones. It may run on another thread than the frames, if
    // that thread leaves the queue and ctx.commandPool alone until it returns (Vulkan wants both externally
    // synchronized). replace waits for the device to be idle, swaps the new sets in and traces the hatching.
    using Sets = std::vector<std::unique_ptr<Refinement>>;
    Sets build(DrawStyle style, const RefineOptions& options) const;
    void replace(Sets newSets, double seconds, const LineOptions& lines = {});

    // The pen lines in two halves too. traceLines does the CPU work for `from` (the current sets or new ones from
    // build): the seeds read back from its first set, and the hatching traced; it may run on the same worker
    // thread as build, under the same rules. setLines puts what it traced in place (waits for the device to be
    // idle; the contour is traced again by the next traceContours). replace(sets, seconds, lines) is
    // replace(sets, seconds, traceLines(sets, lines)).
    struct TracedLines {
        LineOptions options;
        std::vector<SurfaceSample> samples;
        std::vector<PenStroke> hatching;
        HatchStats hatchStats;
        double seconds = 0;  // wall clock
    };
    TracedLines traceLines(const Sets& from, const LineOptions& lines) const;
    // `lines` less the model's lines it has none of (a closed mesh's boundaries, on in every style): no pen lines'
    // work for them.
    LineOptions drawable(LineOptions lines) const;
    void replace(Sets newSets, double seconds, TracedLines traced);
    void setLines(TracedLines traced);
    // Traces the occluding contour seen from `camera` (nothing without LineOptions::contours), on the device
    // where LineOptions::contourTracer says, and replaces the contour strokes on the device (waits for it
    // to be idle).
    void traceContours(const Camera& camera);
    // The sets as the renderer takes them.
    std::vector<const GpuRefinement*> pointers() const;
    // Kept points over all sets (reads the level counts back).
    uint64_t points();

    Context& ctx;

private:
    std::shared_ptr<const Model> model_;

public:
    const Model& model;
    std::vector<std::unique_ptr<Refinement>> sets;
    double refineSeconds = 0;  // of the last refine, wall clock
    LineOptions lines;
    std::unique_ptr<StrokeBuffers> strokes;  // null without pen lines
    std::vector<SurfaceSample> samples;      // the first set's points: seeds of the tracing
    std::vector<PenStroke> hatching, contours;
    HatchStats hatchStats;
    ContourStats contourStats;
    double hatchSeconds = 0;  // tracing and upload

private:
    std::unique_ptr<DeviceContours> deviceContours_;  // for the first set; dropped whenever the sets change
    LineSnap snap_;  // the drawn crease and boundary lines, for the contour to be laid onto (setLines)
    bool notedCpuContours_ = false;
    mutable bool notedCpuField_ = false;
};

}  // namespace ink
