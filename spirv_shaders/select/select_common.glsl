// The stipple selection's bindings and per-point arithmetic (engine/select/select.h explains the method). The C++
// twin of the arithmetic is engine/select/select_math.h: every float expression that decides something is `precise`
// and written in the same order, so that the CPU reference selects exactly the same points.
#ifndef SELECT_COMMON_GLSL
#define SELECT_COMMON_GLSL

#include "common.glsl"

#include "shared/refine.h"  // IndirectArgs
#include "shared/select.h"  // Stage, SelectCounts, SelectParams, the bindings, MAX_STAGES, GROUP_SIZE

layout(std430, binding = SELECT_STAGES) readonly buffer StageBuffer { Stage stages[]; };
// The refinement's points; the candidates are points[first + p], p < candidates.
layout(std430, binding = SELECT_CANDIDATES) readonly buffer CandidateBuffer { Point points[]; };
// The refinement's indirect arguments: its draw (count, 1, first, 0) at `draw`, the selection's after it.
layout(std430, binding = SELECT_INDIRECT) buffer IndirectBuffer { IndirectArgs indirect; };
layout(std430, binding = SELECT_STAGE_OF) buffer StageOfBuffer { uint stageOf[]; };  // 1 + the stage that selected p; 0: not
layout(std430, binding = SELECT_ORDER) buffer OrderBuffer { float order[]; };        // u(p)
layout(std430, binding = SELECT_POOL) buffer PoolBuffer { uint pool[]; };            // candidates by the stage they enter at
// The pool's points by bucket: the point (its `level` holds the candidate index) and its stage state, copied
// so that neighbour searches read memory in order.
layout(std430, binding = SELECT_ENTRY_POINTS) buffer EntryPointBuffer { Point entryPoints[]; };
layout(std430, binding = SELECT_ENTRY_STAGE) buffer EntryStateBuffer { uint entryStage[]; };
const uint COVERED = 0xFFFFFFFFu;  // entryStage of a point within R_s of an earlier stage's (select_cover)
layout(std430, binding = SELECT_BUCKET_COUNT) buffer BucketCountBuffer { uint bucketCount[]; };  // also the scan's input
layout(std430, binding = SELECT_BUCKET_START) buffer BucketStartBuffer { uint bucketStart[]; };  // the scan's output
layout(std430, binding = SELECT_BLOCKS) buffer BlockBuffer { uint blockSums[]; };
layout(std430, binding = SELECT_BACK_FILL) buffer BackFillBuffer { uint backFill[]; };  // select_bucket's back cursors
layout(std430, binding = SELECT_COUNTS) buffer CountBuffer { SelectCounts counts; };
layout(std430, binding = SELECT_STIPPLES) writeonly buffer StippleBuffer { Point stipples[]; };

layout(push_constant) uniform Params { SelectParams pc; };

ivec3 cellOf(vec3 p, Stage s) {
    precise vec3 x = (p + s.offset) * s.cellScale;
    return ivec3(floor(x));
}

uint cellPhase(ivec3 c) { return (uint(c.x) & 1u) | ((uint(c.y) & 1u) << 1) | ((uint(c.z) & 1u) << 2); }

// Buckets of phase k are [k·bucketsPerPhase, (k+1)·bucketsPerPhase); within a phase, the Morton code of the
// 2×2×2 block holding the cell, so that neighbouring cells' buckets, and their points, lie close in memory.
// Far cells may share a bucket (the code wraps): the passes check distances, and cells where they must.
uint spreadBits(uint x) {
    x &= 0x3FFu;
    x = (x | (x << 16u)) & 0x030000FFu;
    x = (x | (x << 8u)) & 0x0300F00Fu;
    x = (x | (x << 4u)) & 0x030C30C3u;
    x = (x | (x << 2u)) & 0x09249249u;
    return x;
}

uint cellBucket(ivec3 c, Stage s) {
    uvec3 block = uvec3(c >> 1);
    uint morton = spreadBits(block.x) | (spreadBits(block.y) << 1u) | (spreadBits(block.z) << 2u);
    return cellPhase(c) * s.bucketsPerPhase + (morton & (s.bucketsPerPhase - 1u));
}

uint stagePriority(Stage s, uint p) { return pcg4d(uvec4(s.seed, p, 0u, 0u)).x; }
uint poolKey(uint seed, uint p) { return pcg4d(uvec4(seed, p, 0x9001u, 0u)).x; }
bool inPool(uint key, Stage s) { return s.poolThreshold == 0xFFFFFFFFu || key < s.poolThreshold; }

bool priorityBefore(uint pa, uint a, uint pb, uint b) { return pa > pb || (pa == pb && a < b); }

// Squared distance of two points on the same side of the surface (normals less than 120° apart), else +inf.
float sameSideDistance2(Point a, Point b) {
    precise float facing = a.normal.x * b.normal.x + a.normal.y * b.normal.y + a.normal.z * b.normal.z;
    if (!(facing > -0.5)) return uintBitsToFloat(0x7F800000u);
    precise float dx = a.position.x - b.position.x;
    precise float dy = a.position.y - b.position.y;
    precise float dz = a.position.z - b.position.z;
    precise float d2 = dx * dx + dy * dy + dz * dz;
    return d2;
}

float additionOrder(Stage s, float d2) {
    precise float u = (s.previousRadius2 - d2) * s.orderScale;
    return u > 0.0 ? min(u, 0.99999994) : 0.0;
}

float firstStageOrder(Stage s, uint p) { return unitFloats(pcg4d(uvec4(s.seed, p, 0xFACEu, 0u))).x; }

Point candidate(uint p) { return points[counts.first + p]; }



#endif
