#version 460
#extension GL_GOOGLE_include_directive : require
// Six vertices a segment of the draw list: a quad around the capsule of its pen width (round ends, so joints
// are smooth), plus a pixel for the antialiasing. The draw mode picks which segments this draw takes; the others,
// and those that do not show (flags 0), become empty triangles.
#include "lines/lines_common.glsl"

layout(location = 0) out vec2 pixel;
layout(location = 1) flat out vec4 ends;
layout(location = 2) flat out vec2 widths;

void main() {
    DrawSegment s = drawList.list[gl_VertexIndex / 6];
    uint mode = cam.counts.y;
    bool take = (mode == 0u && s.flags != 0u) || (mode == 1u && (s.flags & SEG_HIDDEN) != 0u) ||
                (mode == 2u && (s.flags & SEG_INTERIOR) != 0u) || (mode == 3u && (s.flags & SEG_VISIBLE) != 0u);
    vec2 w = s.widths;
    if (mode == 2u) w += lineStyle.widths.w;
    vec2 a = s.ends.xy, b = s.ends.zw, d = b - a;
    vec2 e = length(d) > 1e-6 ? d / length(d) : vec2(1.0, 0.0), side = vec2(-e.y, e.x);
    float r = max(w.x, w.y) + 1.0;
    const vec2 corners[6] = vec2[](vec2(0, -1), vec2(1, -1), vec2(0, 1), vec2(1, -1), vec2(1, 1), vec2(0, 1));
    vec2 c = corners[gl_VertexIndex % 6];
    pixel = (c.x == 0.0 ? a - e * r : b + e * r) + side * (c.y * r);
    ends = s.ends;
    widths = w;
    gl_Position = take ? vec4(pixel / cam.viewport.xy * 2.0 - 1.0, 0.0, 1.0) : vec4(0.0);
}
