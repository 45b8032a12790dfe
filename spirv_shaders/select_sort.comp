#version 460
#extension GL_GOOGLE_include_directive : require
// Sorts the unselected points of every bucket of stage pc.stage by priority (highest first, then by candidate),
// the order select_phase decides them in. They follow the bucketCount[b] selected points select_bucket put
// first. Buckets hold a few points: an insertion sort.
#include "select_common.glsl"

layout(local_size_x = 256) in;

void main() {
    uint b = gl_GlobalInvocationID.x;
    if (b >= 8u * stages[pc.stage].bucketsPerPhase) return;
    uint begin = bucketStart[b] + bucketCount[b], end = bucketStart[b + 1u];
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
