#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The pen lines lines.comp kept (flags not 0), stamped into the frame's coverage bits like the dots (stamp.comp) instead of
// drawn as quads: what a CPU driver is given (lavapipe sets up each triangle on one thread, about 4 µs a
// capsule's two here, 65 ms for the bunny's hatching), chosen by driver ID (LineRenderer). A pixel is inked
// when its centre lies within the capsule (at least half a pixel wide, so thin lines stay connected); no
// antialiasing but the supersampling's. Hatching sets INK_BIT, visible contours CONTOUR_BIT and, if interior,
// HALO_BIT over their halo's width; hidden contours HIDDEN_BIT.
#include "lines/lines_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

// Walks the capsule's major axis, testing across it only the pixels its width reaches.
ivec4 stampCapsule(vec2 a, vec2 b, vec2 w, uint bit) {
    w = max(w, vec2(0.5));
    float r = max(w.x, w.y);
    ivec2 size = ivec2(cam.viewport.xy);
    vec2 d = b - a;
    float dd = max(dot(d, d), 1e-12);
    bool alongX = abs(d.x) >= abs(d.y);
    int axis = alongX ? 0 : 1, across = 1 - axis;
    float major0 = min(a[axis], b[axis]) - r, major1 = max(a[axis], b[axis]) + r;
    int m0 = max(int(floor(major0)), 0), m1 = min(int(ceil(major1)), size[axis] - 1);
    // Across, the centreline moves by slope per pixel; the capsule reaches r / cos beyond it (and r at the caps).
    float slope = abs(d[axis]) > 1e-6 ? d[across] / d[axis] : 0.0;
    float reach = r * sqrt(1.0 + slope * slope) + 1.0;
    ivec4 box = ivec4(0x7FFFFFFF, 0x7FFFFFFF, -1, -1);
    for (int m = m0; m <= m1; ++m) {
        float at = clamp(float(m) + 0.5, min(a[axis], b[axis]), max(a[axis], b[axis]));
        float centre = abs(d[axis]) > 1e-6 ? a[across] + (at - a[axis]) * slope : 0.5 * (a[across] + b[across]);
        float extra = abs(d[axis]) > 1e-6 ? 0.0 : 0.5 * abs(d[across]);
        int c0 = max(int(floor(centre - reach - extra)), 0), c1 = min(int(ceil(centre + reach + extra)), size[across] - 1);
        for (int c = c0; c <= c1; ++c) {
            ivec2 pixel = alongX ? ivec2(m, c) : ivec2(c, m);
            vec2 p = vec2(pixel) + 0.5;
            float t = clamp(dot(p - a, d) / dd, 0.0, 1.0);
            if (length(p - (a + t * d)) > mix(w.x, w.y, t)) continue;
            uint i = uint(pixel.y) * uint(size.x) + uint(pixel.x);
            atomicOr(coverage[i >> 3u], bit << ((i & 7u) * 4u));
            box = ivec4(min(box.xy, pixel), max(box.zw, pixel));
        }
    }
    return box;
}

ivec4 merge(ivec4 x, ivec4 y) { return ivec4(min(x.xy, y.xy), max(x.zw, y.zw)); }

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint count = drawList.draw.x / 6u;
    ivec4 box = ivec4(0x7FFFFFFF, 0x7FFFFFFF, -1, -1);
    if (i < count) {
        DrawSegment s = drawList.list[i];
        vec2 a = s.ends.xy, b = s.ends.zw;
        if (s.flags == 0u) {
            // Does not show.
        } else if (cam.counts.y == 0u) {
            box = stampCapsule(a, b, s.widths, INK_BIT);
        } else if ((s.flags & SEG_VISIBLE) != 0u) {
            if ((s.flags & SEG_INTERIOR) != 0u)
                box = stampCapsule(a, b, s.widths + lineStyle.widths.w, HALO_BIT);
            box = merge(box, stampCapsule(a, b, s.widths, CONTOUR_BIT));
        } else if ((s.flags & SEG_HIDDEN) != 0u) {
            box = stampCapsule(a, b, s.widths, HIDDEN_BIT);
        }
    }
    ivec2 lo = subgroupMin(box.xy), hi = subgroupMax(box.zw);
    if (subgroupElect() && lo.x <= hi.x) {
        atomicMin(drawn.bounds.x, uint(lo.x));
        atomicMin(drawn.bounds.y, uint(lo.y));
        atomicMax(drawn.bounds.z, uint(hi.x));
        atomicMax(drawn.bounds.w, uint(hi.y));
    }
}
