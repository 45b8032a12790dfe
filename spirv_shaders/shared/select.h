// The stipple selection's interface (select_*.comp; engine/select/select.cpp): the stages, the counters, the push
// constants and the descriptor set's bindings (see interface.h). The arithmetic's C++ twin is
// engine/select/select_math.h.
#ifndef INK_SHARED_SELECT_H
#define INK_SHARED_SELECT_H

#include "interface.h"
#include "limits.h"

INK_BEGIN

// One stage of the selection (std430).
struct Stage {
    vec3 offset;            // grid shift
    float cellScale;        // 1 / cell side
    float radius2;          // R_s²
    float previousRadius2;  // R_{s−1}²
    float orderScale;       // 1 / (R_{s−1}² − R_s²)
    uint poolThreshold;     // pool key below this: in the pool (0xFFFFFFFF: every candidate)
    uint bucketsPerPhase;
    uint seed;
    uint pad[2];
};
INK_ASSERT_SIZE(Stage, 48);
INK_ASSERT_OFFSET(Stage, cellScale, 12);
INK_ASSERT_OFFSET(Stage, poolThreshold, 28);
INK_ASSERT_OFFSET(Stage, seed, 36);

// The selection's counters and dispatches (std430).
struct SelectCounts {
    uint candidates;
    uint first;
    uint total;  // points selected
    uint pad;
    uvec4 candidateDispatch;         // over the candidates
    uvec4 poolDispatch[MAX_STAGES];  // over each stage's pool
    uint entering[MAX_STAGES];       // candidates whose first pool is stage s
    uint poolSize[MAX_STAGES];       // candidates in stage s's pool: pool[0 .. poolSize[s])
    uint added[MAX_STAGES];          // points stage s selected
    uint enterFill[MAX_STAGES];      // scatter cursors of the pool sort
    uint before[MAX_STAGES];         // points the stages before s selected
};
INK_ASSERT_SIZE(SelectCounts, 32 + 16 * MAX_STAGES + 5 * 4 * MAX_STAGES);
INK_ASSERT_OFFSET(SelectCounts, candidateDispatch, 16);
INK_ASSERT_OFFSET(SelectCounts, poolDispatch, 32);
INK_ASSERT_OFFSET(SelectCounts, entering, 32 + 16 * MAX_STAGES);
INK_ASSERT_OFFSET(SelectCounts, added, 32 + 16 * MAX_STAGES + 2 * 4 * MAX_STAGES);
INK_ASSERT_OFFSET(SelectCounts, before, 32 + 16 * MAX_STAGES + 4 * 4 * MAX_STAGES);

// The push constants (std430).
struct SelectParams {
    uint stage;
    uint phase;  // select_phase: the phase; select_scan: the pass; the other passes: which of their steps
    uint count;  // scans: elements (0xFFFFFFFF: the candidates)
    uint stageCount;
    uint poolSeed;
};
INK_ASSERT_SIZE(SelectParams, 20);
INK_ASSERT_OFFSET(SelectParams, poolSeed, 16);

// The selection's descriptor set.
INK_CONST uint SELECT_STAGES = 0u;        // Stage[]
INK_CONST uint SELECT_CANDIDATES = 1u;    // the refinement's Point[] (its candidates at points[first + p])
INK_CONST uint SELECT_INDIRECT = 2u;      // the refinement's IndirectArgs (refine.h)
INK_CONST uint SELECT_STAGE_OF = 3u;      // uint[]: 1 + the stage that selected p; 0: not
INK_CONST uint SELECT_ENTRY_POINTS = 4u;  // Point[]: the pool's points by bucket
INK_CONST uint SELECT_ORDER = 5u;         // float[]: u(p)
INK_CONST uint SELECT_POOL = 6u;          // uint[]: candidates by the stage they enter at
INK_CONST uint SELECT_ENTRY_STAGE = 7u;   // uint[]: the pool points' stage state
INK_CONST uint SELECT_BUCKET_COUNT = 8u;  // uint[]: also the scan's input
INK_CONST uint SELECT_BUCKET_START = 9u;  // uint[]: the scan's output
INK_CONST uint SELECT_BLOCKS = 10u;       // uint[]: the scan's block sums
INK_CONST uint SELECT_COUNTS = 11u;       // SelectCounts
INK_CONST uint SELECT_STIPPLES = 12u;     // Point[]: the selected stipples
INK_CONST uint SELECT_BACK_FILL = 13u;    // uint[]: select_bucket's back cursors

INK_END

#endif
