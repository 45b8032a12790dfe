#version 460
#extension GL_GOOGLE_include_directive : require
// The selected points in candidate order (a stable compaction: pc.phase 0 writes the flags the scan sums,
// 1 scatters), each with its rank in the tone field.
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
    uint p = gl_GlobalInvocationID.x;
    if (p >= counts.candidates) return;
    uint k = stageOf[p];
    if (pc.phase == 0u) {
        bucketCount[p] = k != 0u ? 1u : 0u;
    } else if (k != 0u) {
        Point point = candidate(p);
        uint before = counts.before[k - 1u], added = counts.added[k - 1u];
        float rank = (float(before) + order[p] * float(added)) / float(counts.total);
        point.tone = min(rank, 0.99999994);
        stipples[bucketStart[p]] = point;
    }
}
