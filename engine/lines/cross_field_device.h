// The hatching's cross field solved on the device (cross_field.comp, docs/lines.md): the seeds from the fit's
// analytic Hessian at every sample, the restriction to the coarser levels, and every Jacobi sweep and prolongation
// of solveCrossField (cross_field.h), one dispatch a pass, in float, in one submission. The graph is the host's
// (buildCrossFieldGraph), so the device and its CPU twin solve the same problem.
#pragma once

#include "lines/cross_field.h"

namespace ink {

struct Context;
struct GpuRefinement;

// Whether the device solves the field of this refinement's surface: the partition of unity (a global fit is
// evaluated in double, on the CPU).
bool solvesCrossFieldOnDevice(const GpuRefinement& refinement);

// Whether the device's storage buffers hold the graph and the field's state (maxStorageBufferRange).
bool crossFieldFitsDevice(const Context& ctx, const CrossFieldGraph& graph);

// The field on `graph` (built from `samples`) with the surface of `refinement`. `deviceMs`: the passes' time on
// the device (timestamps). Throws ink::Error where the graph does not fit the device's buffers.
CrossFieldSolution solveCrossFieldOnDevice(Context& ctx, const GpuRefinement& refinement,
                                           const std::vector<SurfaceSample>& samples, const CrossFieldGraph& graph,
                                           const CrossFieldOptions& options, double* deviceMs = nullptr);

}  // namespace ink
