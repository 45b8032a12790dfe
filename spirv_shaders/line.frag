#version 460
#extension GL_GOOGLE_include_directive : require
// A pen line: the coverage of the capsule around the segment (its width interpolated along it, tapering at the
// strokes' ends), antialiased over one pixel.
#include "lines_common.glsl"

layout(location = 0) in vec2 pixel;
layout(location = 1) flat in vec4 ends;
layout(location = 2) flat in vec2 widths;
layout(location = 0) out vec4 outColor;

void main() {
    vec2 p = gl_FragCoord.xy, a = ends.xy, d = ends.zw - ends.xy;
    float t = clamp(dot(p - a, d) / max(dot(d, d), 1e-12), 0.0, 1.0);
    float distance = length(p - (a + t * d));
    float coverage = clamp(mix(widths.x, widths.y, t) + 0.5 - distance, 0.0, 1.0);
    if (coverage <= 0.0) discard;
    uint mode = cam.counts.y;
    vec4 color = mode == 1u ? lineStyle.hiddenInk : (mode == 2u ? lineStyle.paper : lineStyle.ink);
    outColor = vec4(color.rgb, color.a * coverage);
}
