#version 460
#extension GL_GOOGLE_include_directive : require
// After select_cover: the unselected points of every bucket of stage pc.stage, which follow the bucketCount[b]
// selected points select_bucket put first, the open ones (not covered) first, sorted by priority (highest
// first, then by candidate), the order select_phase decides them in; the covered ones after them. Buckets hold
// a few points: an insertion sort.
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
    uint b = gl_GlobalInvocationID.x;
    if (b >= 8u * stages[pc.stage].bucketsPerPhase) return;
    uint begin = bucketStart[b] + bucketCount[b], end = bucketStart[b + 1u];
    // The open points first, the covered ones after them (in any order).
    uint open = begin;
    for (uint e = begin; e < end; ++e) {
        if (entryStage[e] != 0u) continue;
        if (e != open) {
            Point point = entryPoints[e];
            entryPoints[e] = entryPoints[open];
            entryStage[e] = COVERED;
            entryPoints[open] = point;
            entryStage[open] = 0u;
        }
        ++open;
    }
    end = open;
    for (uint e = begin + 1u; e < end; ++e) {
        Point point = entryPoints[e];
        uint p = point.level, pp = floatBitsToUint(point.tone);
        uint f = e;
        for (; f > begin; --f) {
            Point previous = entryPoints[f - 1u];
            if (!priorityBefore(pp, p, floatBitsToUint(previous.tone), previous.level)) break;
            entryPoints[f] = previous;
        }
        entryPoints[f] = point;
    }
}
