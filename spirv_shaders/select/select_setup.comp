#version 460
#extension GL_GOOGLE_include_directive : require
// The selection's bookkeeping, one invocation: pc.phase 0, the candidates from the refinement's draw; 1, after
// the pool sort's count, where each stage's pool starts and its dispatch; 2, after the last stage, the rank
// offsets of the stages and the draw of the selected points.
#include "select/select_common.glsl"

layout(local_size_x = 1) in;

void main() {
    if (pc.phase == 0u) {
        counts.candidates = indirect.draw.x;
        counts.first = indirect.draw.z;
        counts.candidateDispatch = uvec4((indirect.draw.x + GROUP_SIZE - 1u) / GROUP_SIZE, 1u, 1u, 0u);
    } else if (pc.phase == 1u) {
        uint size = 0u;
        for (uint s = 0u; s < pc.stageCount; ++s) {
            size += counts.entering[s];
            counts.poolSize[s] = size;
            counts.poolDispatch[s] = uvec4((size + GROUP_SIZE - 1u) / GROUP_SIZE, 1u, 1u, 0u);
        }
    } else {
        uint total = 0u;
        for (uint s = 0u; s < pc.stageCount; ++s) {
            counts.before[s] = total;
            total += counts.added[s];
        }
        counts.total = total;
        indirect.selectedDraw = uvec4(total, 1u, 0u, 0u);
    }
}
