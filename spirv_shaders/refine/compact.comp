#version 460
#extension GL_GOOGLE_include_directive : require
// Stable compaction of one level: kept candidates move to the point buffer in candidate order, so the
// output does not depend on thread scheduling (never an atomic append).
#extension GL_KHR_shader_subgroup_ballot : require
#include "refine/refine_bindings.glsl"

layout(local_size_x = GROUP_SIZE) in;

shared uint subgroupKept[256];

void main() {
    uint L = pc.level, i = gl_GlobalInvocationID.x;
    bool kept = i < levels[L].candidates && flags[i] != 0u;
    uvec4 ballot = subgroupBallot(kept);
    if (subgroupElect()) subgroupKept[gl_SubgroupID] = subgroupBallotBitCount(ballot);
    barrier();
    uint before = 0u;
    for (uint s = 0u; s < gl_SubgroupID; ++s) before += subgroupKept[s];
    if (kept) {
        uint rank = blockSums[gl_WorkGroupID.x] + before + subgroupBallotExclusiveBitCount(ballot);
        points[levels[L].keptOffset + rank] = candidates[i];
    }
}
