#version 460
#extension GL_GOOGLE_include_directive : require
// A pen line: the coverage of the capsule around the segment (its width interpolated along it, tapering at the
// strokes' ends), antialiased over one pixel, over the paper.
#include "lines/lines_common.glsl"

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
    // Blended by MIN (ink: the darker of this and the target) or MAX (a halo: the lighter), so the colour is the
    // line's over the paper, and a pixel that overlapping segments cover takes it once.
    if (mode == 2u) {
        outColor = vec4(lineStyle.paper.rgb * coverage, 1.0);
    } else {
        vec4 color = mode == 1u ? lineStyle.hiddenInk : lineStyle.ink;
        outColor = vec4(mix(lineStyle.paper.rgb, color.rgb, color.a * coverage), 1.0);
    }
}
