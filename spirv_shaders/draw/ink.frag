#version 460
#extension GL_GOOGLE_include_directive : require
// The ink: each pixel a dot (or a stamped pen line) covers takes the ink once — visible ink over hidden ink, a
// halo's paper over both, a contour over all — and blends over the paper, so overlapping dots make no darker
// blots (a pen's line has one tone).
#include "draw/render_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint i = pixel.y * uint(cam.viewport.x) + pixel.x;
    uint bits = coverageBits(i);
    if (bits == 0u || (bits & (CONTOUR_BIT | HALO_BIT)) == HALO_BIT) discard;  // a halo keeps the paper
    outColor = style.color[(bits & (INK_BIT | CONTOUR_BIT)) != 0u ? 0 : 1];
}
