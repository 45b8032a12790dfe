#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum of bucketCount[0 .. n) into bucketStart[0 .. n], the total at n, in three passes
// (pc.phase): 0, each workgroup scans its 256 elements and writes its sum; 1, one workgroup scans the sums;
// 2, each workgroup adds its offset. n = pc.count, or the candidates when it is 0xFFFFFFFF.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "select/select_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

shared uint partial[256];

// Exclusive scan of `value` over the workgroup, subgroup by subgroup (two barriers, whatever the subgroup
// size); the workgroup's total is left in `total`.
shared uint total;
uint workgroupExclusiveScan(uint value) {
    uint inclusive = subgroupInclusiveAdd(value);
    if (gl_SubgroupInvocationID == gl_SubgroupSize - 1u) partial[gl_SubgroupID] = inclusive;
    barrier();
    if (gl_SubgroupID == 0u) {
        // The subgroups' sums, scanned a subgroup-wide chunk at a time.
        uint carry = 0u;
        for (uint base = 0u; base < gl_NumSubgroups; base += gl_SubgroupSize) {
            uint i = base + gl_SubgroupInvocationID;
            uint v = i < gl_NumSubgroups ? partial[i] : 0u;
            uint scanned = subgroupExclusiveAdd(v) + carry;
            if (i < gl_NumSubgroups) partial[i] = scanned;
            carry += subgroupAdd(v);
        }
        if (subgroupElect()) total = carry;
    }
    barrier();
    return partial[gl_SubgroupID] + inclusive - value;
}

void main() {
    uint n = pc.count == 0xFFFFFFFFu ? counts.candidates : pc.count;
    uint t = gl_LocalInvocationIndex, i = gl_GlobalInvocationID.x;
    uint groups = (n + GROUP_SIZE - 1u) / GROUP_SIZE;
    if (pc.phase == 0u) {
        uint value = i < n ? bucketCount[i] : 0u;
        uint prefix = workgroupExclusiveScan(value);
        if (i < n) bucketStart[i] = prefix;
        if (t == 0u) blockSums[gl_WorkGroupID.x] = total;
    } else if (pc.phase == 1u) {
        uint chunk = (groups + 255u) / 256u;
        uint begin = min(t * chunk, groups), end = min(begin + chunk, groups);
        uint sum = 0u;
        for (uint b = begin; b < end; ++b) sum += blockSums[b];
        uint running = workgroupExclusiveScan(sum);
        for (uint b = begin; b < end; ++b) {
            uint v = blockSums[b];
            blockSums[b] = running;
            running += v;
        }
        if (t == 255u) bucketStart[n] = running;
    } else if (i < n) {
        bucketStart[i] += blockSums[gl_WorkGroupID.x];
    }
}
