// The screen spacing of stipples (spacing.comp; docs/algorithm.md §4): the dots a tone asks for, chosen among
// about SPACE_SUPPLY (6) times as many candidates from the surface's ranked blue-noise set, so that on the page
// no two lie closer than a radius the tone sets, whatever the foreshortening. Conflicts go to the lower key (the
// point's rank, a property of the surface point, so that the choice is stable as the camera moves): a parallel greedy
// in rank order, in rounds over a grid of cells that each hold at most one accepted dot. Then a few steps of
// relaxation move each accepted dot, by at most half its radius, away from its nearest (SPACE_RELAX_* in
// shared/render.h): the greedy leaves dots just over a radius apart, the steps spread them towards even spacing.
//
// This file is the CPU twin of spacing.comp: from the same dots it accepts the same ones, bit for bit, and moves
// them to within float rounding (the device's division and square root are not rounded as the CPU's are).
#pragma once

#include "shared/render.h"  // gpu::Dot, SPACE_*

#include <cstdint>
#include <vector>

namespace ink {

// Runs the spacing's SPACE_ROUNDS rounds over `dots` (their pixel, radius, key, point index in cls >> 4 and
// state), as spacing.comp does on a `width` × `height` target with cells of side 1 / inverseCell: OPEN dots end
// ACCEPTED, REJECTED or OPEN (undecided), the others are left alone; then the relaxation moves the ACCEPTED ones.
void spaceDotsOnCpu(std::vector<gpu::Dot>& dots, uint32_t width, uint32_t height, float inverseCell);

}  // namespace ink
