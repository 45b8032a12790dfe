#version 460
#extension GL_GOOGLE_include_directive : require
// Two triangles over the pixels the dots inked (their bounds from stamp.comp), nothing when none were;
// ink.frag colours the covered pixels.
#include "draw/render_common.glsl"

void main() {
    uvec4 b = drawn.bounds;
    const uvec2 corners[6] = uvec2[](uvec2(0, 0), uvec2(1, 0), uvec2(0, 1), uvec2(1, 0), uvec2(1, 1), uvec2(0, 1));
    vec2 pixel = vec2(mix(b.xy, b.zw + 1u, corners[gl_VertexIndex]));
    gl_Position = b.x <= b.z ? vec4(pixel / cam.viewport.xy * 2.0 - 1.0, 0.0, 1.0) : vec4(0.0);
}
