#version 460
#extension GL_GOOGLE_include_directive : require
// Sorts the candidates by the first stage whose pool takes them (a counting sort: pc.phase 0 counts, 1
// scatters), so that stage s's pool is the prefix pool[0 .. poolSize[s]). Within a group the order is left to
// the atomics: the stages treat a pool as a set.
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
    uint p = gl_GlobalInvocationID.x;
    if (p >= counts.candidates) return;
    uint key = poolKey(pc.poolSeed, p);
    uint s = 0u;
    while (s + 1u < pc.stageCount && !inPool(key, stages[s])) ++s;
    if (pc.phase == 0u) {
        atomicAdd(counts.entering[s], 1u);
    } else {
        uint slot = atomicAdd(counts.enterFill[s], 1u);
        pool[counts.poolSize[s] - counts.entering[s] + slot] = p;
    }
}
