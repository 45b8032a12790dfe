#version 460
#extension GL_GOOGLE_include_directive : require
// Before the phases of stage pc.stage, one invocation per pool point: a point within R_s of a point an earlier
// stage selected can never be selected here, whatever the order, so it is marked COVERED now, in parallel,
// and the phases decide only the others. Those get their order u here too: the distance to the earlier
// stages' points is final before the phases begin.
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= counts.poolSize[pc.stage] || entryStage[e] != 0u) return;
    Stage s = stages[pc.stage];
    Point a = entryPoints[e];
    ivec3 c = cellOf(a.position, s);
    bool covered = false;
    float nearest = uintBitsToFloat(0x7F800000u);
    // The own cell first: a cover, the usual outcome, ends the search early.
    for (uint n = 0u; !covered && n < 27u; ++n) {
        uint m = (n + 13u) % 27u;
        ivec3 cell = c + ivec3(m % 3u, (m / 3u) % 3u, m / 9u) - 1;
        uint nb = cellBucket(cell, s);
        uint first = bucketStart[nb], last = first + bucketCount[nb];  // the selected points
        for (uint f = first; !covered && f < last; ++f) {
            Point other = entryPoints[f];
            float d2 = sameSideDistance2(a, other);
            if (d2 < s.radius2) covered = true;
            // Another cell's point in the same bucket is not among the 27 cells the reference reads.
            else if (d2 < nearest && cellOf(other.position, s) == cell) nearest = d2;
        }
    }
    if (covered)
        entryStage[e] = COVERED;
    else
        order[a.level] = pc.stage == 0u ? firstStageOrder(s, a.level) : additionOrder(s, nearest);
}
