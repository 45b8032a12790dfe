#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The dots splat.comp selected, in four passes (cam.counts.w). PASS_VISIBILITY tests each against the splat depth
// (occluded ones vanish, or become hidden silhouettes) and opens the visible toned ones to the screen spacing
// (spacing.comp); PASS_OUTLINE and PASS_REACH make each silhouette dot the stroke to its neighbours along the
// outline; PASS_STAMP stamps the visible ones the spacing kept into the coverage bits that ink.frag turns into
// colour. Dots are rasterized here rather than drawn as point primitives: a CPU driver sets up each point
// primitive on one thread (lavapipe: ~0.45 µs a point, whatever its size and shaders), while a stamp is a few
// atomic ORs.
#include "draw/render_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

// Sets the pixels whose centres lie within the dot's disk, swept from center − along to center + along (a
// silhouette's stroke; along = 0 for a round dot), and always the pixel under its centre, so that a dot smaller
// than a pixel never vanishes between pixel centres. Returns the pixel box it may have set.
ivec4 stamp(vec2 center, float diameter, vec2 along, uint bit) {
    float r = 0.5 * diameter, along2 = dot(along, along);
    vec2 reach = abs(along) + r;
    ivec2 size = ivec2(cam.viewport.xy);
    ivec2 own = ivec2(floor(center));
    ivec2 lo = max(min(ivec2(ceil(center - reach - 0.5)), own), ivec2(0));
    ivec2 hi = min(max(ivec2(floor(center + reach - 0.5)), own), size - 1);
    for (int y = lo.y; y <= hi.y; ++y) {
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 d = vec2(x, y) + 0.5 - center;
            if (along2 > 0.0) d -= along * clamp(dot(d, along) / along2, -1.0, 1.0);  // from the nearest on the stroke
            if (dot(d, d) > r * r && ivec2(x, y) != own) continue;
            uint i = uint(y) * uint(size.x) + uint(x);
            atomicOr(coverage[i >> COVERAGE_SHIFT], bit << ((i & 7u) * COVERAGE_BITS));
        }
    }
    return ivec4(lo, hi);
}

// The distance along the view axis of a point at normalized depth `ndc` (view z = −P32 / (ndc + P22)).
float viewDepth(float ndc) { return cam.projection.w / (ndc + cam.projection.z); }

// The normalized depth of a point at normalized depth `ndc` moved `pushBacks` push-backs away from the camera.
float pushedBack(float ndc, float pushBacks) {
    float view = -viewDepth(ndc) - pushBacks * cam.splat.y;
    return -cam.projection.z - cam.projection.w / view;
}

// The depth grid's cell under a pixel, and a cell's word: the nearest splat's normalized depth as float bits (bit 0
// marks the back of an open surface, CAMERA_TWO_SIDED).
ivec2 depthCell(vec2 pixel) {
    ivec2 grid = ivec2(cam.viewport.zw);
    return clamp(ivec2(pixel / cam.viewport.xy * vec2(grid)), ivec2(0), grid - 1);
}
uint depthWord(ivec2 cell) { return depth[cell.y * int(cam.viewport.z) + cell.x]; }

// Whether cells nearer than depth `z` lie left, right, above and below `cell`, each within SPLAT_HOLE splat radii
// (at z): the dot lies in a hole in the splats, behind the surface around it. The refinement leaves gaps of a few
// times its spacing that no disk covers (the targets' torus: up to 6 nearest-neighbour distances), and a dot of the
// surface behind showed through one as a lone dot, larger than those around it (the spacing enlarges far dots).
// An outline's dot has open ground beyond it; the bottom of a pit narrower than the search is hidden with it.
bool enclosed(float z, ivec2 cell) {
    vec2 grid = cam.viewport.zw;
    int most = clamp(int(ceil(SPLAT_HOLE * cam.splat.x * abs(cam.projection.x) * 0.5 * grid.x / max(viewDepth(z), 1e-6))),
                     1, SPLAT_HOLE_CELLS);
    const ivec2 ways[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    for (int w = 0; w < 4; ++w) {
        bool nearer = false;
        for (int k = 1; k <= most && !nearer; ++k) {
            ivec2 c = cell + k * ways[w];
            if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(grid)))) break;
            nearer = uintBitsToFloat(depthWord(c)) < z;
        }
        if (!nearer) return false;
    }
    return true;
}

// The dot's class once occlusion is known: as selected, HIDDEN, or BACK for a dot that does not show.
uint visibleClass(Dot d) {
    uint cls = d.cls & 3u;
    if (cam.splat.y <= 0.0) return cls;  // no occlusion
    ivec2 grid = ivec2(cam.viewport.zw), cell = depthCell(d.pixel);
    // (Direction sampling's sparse disks keep to their rims: there a hole is no gap.)
    bool sparse = (cam.counts.y & CAMERA_SPARSE_SPLATS) != 0u;
    bool shows = d.z <= uintBitsToFloat(depthWord(cell)) && (sparse || !enclosed(d.z, cell));
    if (shows && (d.cls & DOT_BACK_SIDE) != 0u) {
        // The back of an open surface shows in front of every front-facing disk in its cell and the cells around
        // (a cell the front surface's disks leave uncovered is no opening), tested two push-backs farther.
        float z = pushedBack(d.z, 2.0);
        ivec2 lo = max(cell - 1, ivec2(0)), hi = min(cell + 1, grid - 1);
        for (int y = lo.y; y <= hi.y && shows; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                uint nearest = depthWord(ivec2(x, y));
                if ((nearest & 1u) == 0u && z > uintBitsToFloat(nearest)) shows = false;
            }
    }
    if (shows) return cls;
    return cls == SILHOUETTE && (cam.counts.y & CAMERA_HIDDEN) != 0u ? HIDDEN : BACK;
}

// Whether a visible silhouette dot shows at its own depth (not two push-backs nearer, as splat.comp tests it) in its
// depth cell or one of the eight around: an outline's dot does, beside what lies behind the outline. A dot of a
// contour just behind a surface at a graze may pass the lenient test (the torus's inner contour under its front
// tube): drawn as a stroke it was a dash on the surface in front, so it stays a round dot, lost among the stipples,
// and out of the other strokes' reach.
bool bordersBehind(Dot d) {
    if (cam.splat.y <= 0.0) return true;
    ivec2 cell = depthCell(d.pixel);
    float z = pushedBack(d.z, 2.0);
    ivec2 lo = max(cell - 1, ivec2(0)), hi = min(cell + 1, ivec2(cam.viewport.zw) - 1);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            if (z <= uintBitsToFloat(depthWord(ivec2(x, y)))) return true;
    return false;
}

// Whether pixel p holds `bit` in the coverage (false off the target).
bool inked(vec2 p, uint bit) {
    ivec2 q = ivec2(floor(p));
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(cam.viewport.xy)))) return false;
    uint i = uint(q.y) * uint(cam.viewport.x) + uint(q.x);
    return (coverageBits(i) & bit) != 0u;
}

// How far from `center` along `dir` the nearest other outline disk lies, up to `most` pixels (0: none): the first
// pixel step past the dot's own disk (radius r) where the coverage holds `bit` on the line or a pixel beside it.
float reach(vec2 center, vec2 dir, float r, float most, uint bit) {
    vec2 side = vec2(-dir.y, dir.x);
    for (float s = r + 1.0; s <= most; s += 1.0) {
        vec2 p = center + s * dir;
        if (inked(p, bit) || inked(p + side, bit) || inked(p - side, bit)) return s;
    }
    return 0.0;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    Dot d = list.dots[min(i, list.dispatch.w - 1u)];
    if (cam.counts.w == PASS_VISIBILITY) {
        if (i >= list.dispatch.w) return;
        uint cls = visibleClass(d);
        list.dots[i].cls = d.cls >> 3u << 4u | cls << 2u | (d.cls & 3u);
        if (cls == SILHOUETTE && !bordersBehind(d)) list.dots[i].along = vec2(0.0);  // round
        if (cls == BACK) list.dots[i].state = SPACE_FIXED;
        return;
    }
    if (cam.counts.w == PASS_OUTLINE || cam.counts.w == PASS_REACH) {
        // A silhouette's stroke joins its dot to the nearest outline dots ahead and behind along the outline, within
        // reach (Dot::along, splat.comp); with none it stays round, and it never overshoots the outline's end.
        uint cls = (d.cls >> 2u) & 3u;
        if (i >= list.dispatch.w || (d.cls & 3u) != SILHOUETTE || cls == BACK || !(dot(d.along, d.along) > 0.0)) return;
        float diameter = clamp(style.size[cls == HIDDEN ? 2u : 0u], style.tone.z, style.tone.w);
        uint bit = cls == HIDDEN ? HIDDEN_BIT : INK_BIT;
        if (cam.counts.w == PASS_OUTLINE) {
            stamp(d.pixel, diameter, vec2(0.0), bit);
            return;
        }
        vec2 dir = normalize(d.along);
        float most = length(d.along), r = 0.5 * diameter;
        float ahead = reach(d.pixel, dir, r, most, bit), behind = reach(d.pixel, -dir, r, most, bit);
        list.dots[i].pixel = d.pixel + 0.5 * (ahead - behind) * dir;
        list.dots[i].along = 0.5 * (ahead + behind) * dir;
        return;
    }
    uint cls = (d.cls >> 2u) & 3u;
    bool visible = i < list.dispatch.w && cls != BACK && (d.state == SPACE_FIXED || d.state == SPACE_ACCEPTED);
    ivec4 box = ivec4(0x7FFFFFFF, 0x7FFFFFFF, -1, -1);
    if (visible) {
        uint sizeSlot = cls == HIDDEN ? 2u : cls;
        box = stamp(d.pixel, clamp(style.size[sizeSlot] * d.scale, style.tone.z, style.tone.w), d.along,
                    cls == HIDDEN ? HIDDEN_BIT : INK_BIT);
    } else if (i < list.dispatch.w && cls != BACK) {
        list.dots[i].cls = d.cls & ~12u | BACK << 2u;  // spaced out: not drawn
    }
    // One atomic a subgroup for the count and the bounds.
    uint dots = subgroupBallotBitCount(subgroupBallot(visible));
    ivec2 lo = subgroupMin(box.xy), hi = subgroupMax(box.zw);
    if (subgroupElect() && dots > 0u) {
        atomicAdd(drawn.dotCount.x, dots);
        atomicMin(drawn.bounds.x, uint(lo.x));
        atomicMin(drawn.bounds.y, uint(lo.y));
        atomicMax(drawn.bounds.z, uint(hi.x));
        atomicMax(drawn.bounds.w, uint(hi.y));
    }
}
