// A model and its point sets on one device: what `render`, `capture` and the viewer draw, and what an
// embedding application keeps between frames.
#pragma once

#include "model.h"
#include "refine.h"

#include <memory>
#include <vector>

namespace ink {

// Stipples, hatch-like lines of dots (direction sampling), or both sets drawn together.
enum class DrawStyle { Stipple, Direction, Both };
const char* drawStyleName(DrawStyle style);  // "stipple", "direction", "both"

class Scene {
public:
    // Refines the model for the style: one submission a set, waited for.
    Scene(Context& ctx, Model model, DrawStyle style, const RefineOptions& options);
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // Replaces the point sets (new levels, another style); waits for the device to be idle first, since a
    // frame in flight may still read the old ones.
    void refine(DrawStyle style, const RefineOptions& options);
    // The sets as the renderer takes them.
    std::vector<const GpuRefinement*> pointers() const;
    // Kept points over all sets (reads the level counts back).
    uint64_t points();

    Context& ctx;
    Model model;
    std::vector<std::unique_ptr<Refinement>> sets;
    double refineSeconds = 0;  // of the last refine, wall clock
};

}  // namespace ink
