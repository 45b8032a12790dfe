#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum of bucketCount[0 .. n) into bucketStart[0 .. n], the total at n, in three passes
// (pc.phase): 0, each workgroup scans its 256 elements and writes its sum; 1, one workgroup scans the sums;
// 2, each workgroup adds its offset. n = pc.count, or the candidates when it is 0xFFFFFFFF.
#include "select_common.glsl"

layout(local_size_x = 256) in;

shared uint partial[256];

// Exclusive scan of `value` over the workgroup; returns the element's prefix, leaves the sum in partial[255]
// plus the last value (the caller adds it).
uint workgroupExclusiveScan(uint value) {
    uint t = gl_LocalInvocationIndex;
    partial[t] = value;
    barrier();
    for (uint offset = 1u; offset < 256u; offset <<= 1u) {
        uint add = t >= offset ? partial[t - offset] : 0u;
        barrier();
        partial[t] += add;
        barrier();
    }
    return partial[t] - value;  // inclusive minus own
}

void main() {
    uint n = pc.count == 0xFFFFFFFFu ? counts.candidates : pc.count;
    uint t = gl_LocalInvocationIndex, i = gl_GlobalInvocationID.x;
    uint groups = (n + GROUP_SIZE - 1u) / GROUP_SIZE;
    if (pc.phase == 0u) {
        uint value = i < n ? bucketCount[i] : 0u;
        uint prefix = workgroupExclusiveScan(value);
        if (i < n) bucketStart[i] = prefix;
        if (t == 255u) blockSums[gl_WorkGroupID.x] = partial[255];
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
