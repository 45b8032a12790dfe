#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum of the per-workgroup kept counts of one level, in one workgroup, then the level's
// bookkeeping: where its points go, how many children the next level has, its dispatch and the draw.
#include "refine/refine_bindings.glsl"

layout(local_size_x = GROUP_SIZE) in;

shared uint partial[256];

void main() {
    uint L = pc.level, t = gl_LocalInvocationIndex;
    uint groups = (levels[L].candidates + GROUP_SIZE - 1u) / GROUP_SIZE;
    uint chunk = (groups + 255u) / 256u;
    uint begin = min(t * chunk, groups), end = min(begin + chunk, groups);

    uint sum = 0u;
    for (uint b = begin; b < end; ++b) sum += blockSums[b];
    partial[t] = sum;
    barrier();
    if (t == 0u) {
        uint running = 0u;
        for (uint k = 0u; k < 256u; ++k) {
            uint v = partial[k];
            partial[k] = running;
            running += v;
        }
        uint offset = L == 0u ? 0u : levels[L - 1u].keptOffset + levels[L - 1u].kept;
        levels[L].keptOffset = offset;
        levels[L].kept = running;
        if (pc.nextChildCount != 0u) {
            uint next = running * pc.nextChildCount;
            levels[L + 1u].candidates = next;
            levels[L + 1u].parentOffset = offset;
            indirect.dispatches[L + 1u] = uvec4((next + GROUP_SIZE - 1u) / GROUP_SIZE, 1u, 1u, 0u);
        }
        indirect.draw = pc.keepAll != 0u ? uvec4(offset + running, 1u, 0u, 0u) : uvec4(running, 1u, offset, 0u);
    }
    barrier();
    uint running = partial[t];
    for (uint b = begin; b < end; ++b) {
        uint v = blockSums[b];
        blockSums[b] = running;
        running += v;
    }
}
