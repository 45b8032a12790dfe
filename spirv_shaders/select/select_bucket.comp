#version 460
#extension GL_GOOGLE_include_directive : require
// Stage pc.stage's pool into its buckets: pc.phase 0 counts the points of each bucket, 1 (after the scan)
// scatters copies into entryPoints[] (`level`: the candidate, `tone`: its priority's bits). The order within a
// bucket is left to the atomics; select_sort sorts it.
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counts.poolSize[pc.stage]) return;
    Stage s = stages[pc.stage];
    uint p = pool[i];
    Point point = candidate(p);
    uint b = cellBucket(cellOf(point.position, s), s);
    if (pc.phase == 0u) {
        atomicAdd(bucketCount[b], 1u);
    } else {
        // The points earlier stages selected from the front, bucketCount[b] of them in the end; the others from
        // the back, counted in backFill.
        uint state = stageOf[p];
        uint e = state != 0u ? bucketStart[b] + atomicAdd(bucketCount[b], 1u)
                             : bucketStart[b + 1u] - 1u - atomicAdd(backFill[b], 1u);
        point.level = p;
        point.tone = uintBitsToFloat(stagePriority(s, p));
        entryPoints[e] = point;
        entryStage[e] = state;
    }
}
