#version 460
#extension GL_GOOGLE_include_directive : require
// One phase of stage pc.stage: one invocation per bucket of the phase decides the bucket's unselected points,
// highest priority first, against the points selected so far. Every bucket keeps its selected points first,
// bucketCount[b] of them, so a search reads only those. The cells of a phase are more than R_s apart and the
// buckets of a phase hold only its cells, so the invocations never read what another one writes.
#include "select/select_common.glsl"

layout(local_size_x = PHASE_GROUP_SIZE) in;

void main() {
    Stage s = stages[pc.stage];
    uint local = gl_GlobalInvocationID.x;
    if (local >= s.bucketsPerPhase) return;
    uint b = pc.phase * s.bucketsPerPhase + local;
    uint begin = bucketStart[b], end = bucketStart[b + 1u];
    uint selectedEnd = begin + bucketCount[b];
    // The unselected points follow, sorted by priority (select_sort); select_cover marked those an earlier
    // stage's point covers, so only this stage's points can stop the others.
    for (uint e = selectedEnd; e < end; ++e) {
        if (entryStage[e] != 0u) break;  // the covered points, after the open ones (select_sort)
        Point a = entryPoints[e];
        ivec3 c = cellOf(a.position, s);
        bool free = true;
        for (uint n = 0u; free && n < 27u; ++n) {
            uint m = (n + 13u) % 27u;
            ivec3 cell = c + ivec3(m % 3u, (m / 3u) % 3u, m / 9u) - 1;
            // Cells of later phases hold no point of this stage yet.
            if (cellPhase(cell) > pc.phase) continue;
            uint nb = cellBucket(cell, s);
            uint first = bucketStart[nb], last = nb == b ? selectedEnd : first + bucketCount[nb];
            for (uint f = first; free && f < last; ++f)
                if (entryStage[f] == pc.stage + 1u && sameSideDistance2(a, entryPoints[f]) < s.radius2) free = false;
        }
        if (free) {
            // Into the selected prefix; the point there (decided already) takes this one's place.
            uint p = a.level;
            entryPoints[e] = entryPoints[selectedEnd];
            entryStage[e] = entryStage[selectedEnd];
            entryPoints[selectedEnd] = a;
            entryStage[selectedEnd] = pc.stage + 1u;
            ++selectedEnd;
            stageOf[p] = pc.stage + 1u;
            atomicAdd(counts.added[pc.stage], 1u);
        }
    }
    bucketCount[b] = selectedEnd - begin;
}
