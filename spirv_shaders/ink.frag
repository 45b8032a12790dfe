#version 460
#extension GL_GOOGLE_include_directive : require
// The ink: each pixel a dot covers takes the ink once — visible dots over hidden ones — and blends over the
// paper, so overlapping dots make no darker blots (a pen's line has one tone).
#include "render_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint i = pixel.y * uint(cam.viewport.x) + pixel.x;
    uint bits = (coverage[i >> 4u] >> ((i & 15u) * 2u)) & 3u;
    if (bits == 0u) discard;
    outColor = style.color[(bits & INK_BIT) != 0u ? 0 : 1];
}
