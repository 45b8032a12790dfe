#version 460
#extension GL_GOOGLE_include_directive : require
// After lines.comp, once per contour, crease or boundary segment and frame: the segment shows visible or hidden as
// most of its stroke does within lineStyle.features.z of the image's shorter side either way (by length in the
// image), a median along the stroke. Where visibility truly changes the longer runs either side win and the
// change stays where it was; a run shorter than the window, which the depth grid's cells flip near an outline or
// a cusp, takes its neighbours' state: no dashes. Reads lines.comp's own decisions (SEG_RAW_*, in `segment`, which
// this pass does not write) and rewrites each segment's flags and widths in its own slot.
#include "lines/lines_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

float pixels(DrawSegment s) { return length(s.ends.zw - s.ends.xy); }

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cam.counts.x) return;
    DrawSegment s = drawList.list[i];
    if ((s.segment & SEG_RAW_SHOWN) == 0u) return;  // hatching, or not in the image
    uint kind = floatBitsToUint(texelFetch(segments, int(3u * i + 2u)).w);
    uint before = (kind >> SEG_BEFORE_SHIFT) & SEG_REACH, after = (kind >> SEG_AFTER_SHIFT) & SEG_REACH;
    const float window = lineStyle.features.z * min(cam.viewport.x, cam.viewport.y);
    // Length shown visible and hidden: this segment, then its neighbours until the window is covered, the stroke
    // ends or leaves the image.
    float visible = 0.0, hidden = 0.0;
    float own = pixels(s);
    if ((s.segment & SEG_RAW_VISIBLE) != 0u) visible += own; else hidden += own;
    float reach = 0.5 * own;
    for (uint k = 1u; k <= before && reach < window; ++k) {
        DrawSegment t = drawList.list[i - k];
        if ((t.segment & SEG_RAW_SHOWN) == 0u) break;
        float p = min(pixels(t), window - reach);
        if ((t.segment & SEG_RAW_VISIBLE) != 0u) visible += p; else hidden += p;
        reach += p;
    }
    reach = 0.5 * own;
    for (uint k = 1u; k <= after && reach < window; ++k) {
        DrawSegment t = drawList.list[i + k];
        if ((t.segment & SEG_RAW_SHOWN) == 0u) break;
        float p = min(pixels(t), window - reach);
        if ((t.segment & SEG_RAW_VISIBLE) != 0u) visible += p; else hidden += p;
        reach += p;
    }
    bool wasVisible = (s.segment & SEG_RAW_VISIBLE) != 0u;
    bool shows = visible == hidden ? wasVisible : visible > hidden;
    if (shows == wasVisible) return;  // lines.comp's flags stand
    vec4 t0 = texelFetch(segments, int(3u * i)), t1 = texelFetch(segments, int(3u * i + 1u));
    // Flipped: no halo for a contour made visible (its interior test was not made), nothing for a hidden one
    // unless hidden lines are drawn.
    drawList.list[i].flags = shows ? SEG_VISIBLE : (lineStyle.options.y != 0.0 ? SEG_HIDDEN : 0u);
    bool feature = (kind & (KIND_CREASE | KIND_BOUNDARY)) != 0u;  // their w is a standoff (lines.h)
    drawList.list[i].widths = 0.5 * lineWidth(kind, shows) * (feature ? vec2(1.0) : vec2(t0.w, t1.w));
}
