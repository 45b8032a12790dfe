// Descriptor set shared by the three refinement passes (refine, scan, compact). See engine/refine/refine.cpp.
#ifndef REFINE_BINDINGS_GLSL
#define REFINE_BINDINGS_GLSL

#include "common.glsl"
#include "shared/limits.h"  // GROUP_SIZE

layout(std430, binding = REFINE_POINTS) buffer PointBuffer { Point points[]; };
layout(std430, binding = REFINE_CANDIDATES) buffer CandidateBuffer { Point candidates[]; };
layout(std430, binding = REFINE_FLAGS) buffer FlagBuffer { uint flags[]; };      // 1 = kept, per candidate
layout(std430, binding = REFINE_BLOCKS) buffer BlockBuffer { uint blockSums[]; };  // kept per workgroup, then its offset
layout(std430, binding = REFINE_LEVELS) buffer LevelBuffer { LevelInfo levels[MAX_LEVELS]; };
layout(std430, binding = REFINE_INDIRECT) buffer IndirectBuffer { IndirectArgs indirect; };
layout(std430, binding = REFINE_SEEDS) readonly buffer SeedBuffer { vec4 seeds[]; };  // xyz start, w parent index

layout(push_constant) uniform Params { RefineParams pc; };

#endif
