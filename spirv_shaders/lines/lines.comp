#version 460
#extension GL_GOOGLE_include_directive : require
// Once per traced segment and frame: whether it shows, against the splat depth grid the dots' pass built.
// - Contours: visible when not behind the surface (tested two push-backs nearer the camera, as silhouette dots
//   are) and not a piece its own surface hides (KIND_OCCLUDED), else hidden; interior when there is surface on
//   both sides of it in the image (it lies in front of more surface), which gets the halo.
// - Hatching: drawn where its surface faces the camera, its tone is dark enough for its family and level, and it is
//   not behind the surface, over a run of its stroke long enough to read as a stroke (tone.w pixels). The strokes
//   are fixed to the model; only these per-frame decisions change.
// - Crease and boundary lines: visible when not behind the surface at their own pixel (tested four push-backs
//   nearer the camera: they run along the surface, not beside it), and for a closed part's crease (KIND_FACED)
//   when one of its two faces turns towards the eye (a crease between two back faces stands out past the outline
//   within those push-backs: the stubs at a box's far corners), else hidden like contours.
// Contour, crease and boundary lines then take the visibility most of their stroke around them has
// (lines_runs.comp).
// Each segment's decision goes to its own slot of the draw list (flags 0 where nothing of it shows; hidden
// hatching is dropped), so the list's order, and with it the blending of overlapping lines, does not depend on
// how the device schedules the threads: a GPU draws every frame the same, bit for bit.
#include "lines/lines_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

uint depthAt(vec2 pixel) {
    vec2 grid = cam.viewport.zw;
    ivec2 cell = clamp(ivec2(pixel / cam.viewport.xy * grid), ivec2(0), ivec2(grid) - 1);
    return depth[cell.y * int(grid.x) + cell.x];
}

vec2 toPixels(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * cam.viewport.xy; }

// Whether a point of an open surface's back (CAMERA_TWO_SIDED) lies behind a front-facing disk of its depth cell or
// the eight around by more than two push-backs: hidden then, as stamp.comp hides the back's dots (the depth's lowest
// bit clear: written by a front-facing disk), so that a closed part's back does not show at folds and thin parts.
bool behindFront(vec3 p) {
    vec4 farther = project(p + normalize(p) * (2.0 * cam.params.x));
    float z = farther.z / farther.w;
    vec2 grid = cam.viewport.zw;
    ivec2 cell = clamp(ivec2(toPixels(farther) / cam.viewport.xy * grid), ivec2(0), ivec2(grid) - 1);
    ivec2 lo = max(cell - 1, ivec2(0)), hi = min(cell + 1, ivec2(grid) - 1);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            uint nearest = depth[y * int(grid.x) + x];
            if ((nearest & 1u) == 0u && z > uintBitsToFloat(nearest)) return true;
        }
    return false;
}

// Whether hatching segment `index` shows: it faces the camera, its tone is dark enough for its family and level,
// and it is not behind the surface (tested one push-back nearer the camera against the depth grid; past the
// image's edge, where there is no depth to test, a segment the walk reaches counts, so that strokes are not cut
// short at the border). `pixels`: its length in the image.
bool hatchShows(uint index, out float pixels) {
    vec4 t0 = texelFetch(segments, int(3u * index)), t1 = texelFetch(segments, int(3u * index + 1u)),
         t2 = texelFetch(segments, int(3u * index + 2u));
    uint kind = floatBitsToUint(t2.w);
    vec3 a = (cam.view * vec4(t0.xyz, 1.0)).xyz, b = (cam.view * vec4(t1.xyz, 1.0)).xyz;
    vec3 mid = 0.5 * (a + b), n = mat3(cam.view) * t2.xyz;
    pixels = -a.z > 1e-6 && -b.z > 1e-6 ? length(toPixels(project(b)) - toPixels(project(a))) : 0.0;
    float nv = dot(n, -normalize(mid));
    vec3 normal = t2.xyz;
    bool back = cam.params.z != 0.0 && nv < 0.0;
    if (back) {  // an open surface seen from behind: its other side (CAMERA_TWO_SIDED)
        n = -n;
        nv = -nv;
        normal = -normal;
    }
    uint family = (kind >> HATCH_FAMILY_SHIFT) & 3u, level = (kind >> HATCH_LEVEL_SHIFT) & 1u;
    float lit = max(0.0, dot(lineStyle.options.x != 0.0 ? normal : n, lineStyle.light.xyz));
    float darkness = (lineStyle.tone.y + pow(1.0 - lit, max(lineStyle.light.w, 1e-3))) * lineStyle.tone.x;
    float threshold = family < 2u ? lineStyle.thresholds[family * 2u + level] : lineStyle.diagonal[level];
    // The diagonal family needs the surface turned towards the eye more (diagonal.z): beside an outline the view
    // crowds three families into one grey, and the diagonal's runs there come out short.
    if (!(nv > (family < 2u ? lineStyle.tone.z : lineStyle.diagonal.z) && darkness > threshold)) return false;
    vec4 nearer = project(mid - normalize(mid) * cam.params.x);
    vec2 pixel = toPixels(nearer);
    if (any(lessThan(pixel, vec2(0.0))) || any(greaterThanEqual(pixel, cam.viewport.xy))) return true;
    return nearer.z / nearer.w <= uintBitsToFloat(depthAt(pixel)) && !(back && behindFront(mid));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint index = min(i, max(cam.counts.x, 1u) - 1u);
    vec4 t0 = texelFetch(segments, int(3u * index)), t1 = texelFetch(segments, int(3u * index + 1u)),
         t2 = texelFetch(segments, int(3u * index + 2u));
    uint kind = floatBitsToUint(t2.w);
    bool hatch = (kind & KIND_HATCH) != 0u, feature = (kind & (KIND_CREASE | KIND_BOUNDARY)) != 0u;
    vec3 a = (cam.view * vec4(t0.xyz, 1.0)).xyz, b = (cam.view * vec4(t1.xyz, 1.0)).xyz;
    vec3 mid = 0.5 * (a + b);
    vec3 n = mat3(cam.view) * t2.xyz;
    bool keep = i < cam.counts.x && -a.z > 1e-6 && -b.z > 1e-6;
    uint flags = 0u, raw = 0u;  // raw: this pass's decision for lines_runs.comp (contour, crease, boundary)
    vec4 ca = project(a), cb = project(b);
    vec2 pa = toPixels(ca), pb = toPixels(cb);
    // Off screen (with a margin for the pen).
    vec2 lo = min(pa, pb), hi = max(pa, pb);
    keep = keep && all(greaterThan(hi, vec2(-8.0))) && all(lessThan(lo, cam.viewport.xy + 8.0));
    float width;
    if (hatch) {
        // Wanted by its tone and facing, not behind the surface, and within a run of such segments of its stroke
        // at least tone.w of the image long: walked both ways along the stroke until the run ends or is long
        // enough. Visibility is part of the run: a stroke hidden behind a nearer part of the surface, where the
        // depth grid has a gap, would otherwise show through it as a dash.
        const float minRun = lineStyle.tone.w * min(cam.viewport.x, cam.viewport.y);
        float run;
        keep = keep && hatchShows(index, run);
        uint before = (kind >> SEG_BEFORE_SHIFT) & SEG_REACH, after = (kind >> SEG_AFTER_SHIFT) & SEG_REACH;
        float pixels;
        for (uint k = 1u; keep && k <= before && run < minRun && hatchShows(index - k, pixels); ++k)
            run += pixels;
        for (uint k = 1u; keep && k <= after && run < minRun && hatchShows(index + k, pixels); ++k)
            run += pixels;
        keep = keep && run >= minRun;
        flags = SEG_VISIBLE;
        width = lineStyle.widths.z;
    } else if (feature) {
        // Two push-backs, and the line's standoff (how far it lies behind the surface the eye sees: inside the fit's
        // fillet of a concave crease) as far along the view as the faces' mean normal makes it, at most four times.
        // Four push-backs alone let creases behind thin walls show (CGAL's cheese).
        vec3 facing = dot(n, n) > 1e-12 ? normalize(n) : vec3(0.0);
        float standoff = 0.5 * (t0.w + t1.w) / max(abs(dot(facing, normalize(mid))), 0.25);
        vec4 nearer = project(mid - normalize(mid) * (2.0 * cam.params.x + standoff));
        bool visible = nearer.z / nearer.w <= uintBitsToFloat(depthAt(toPixels(nearer)));
        if ((kind & KIND_FACED) != 0u) {
            // t2.xyz: the mean m of the faces' unit normals n₁, n₂ (length cos(α/2)). With u the unit vector across
            // the edge in their plane, n₁,₂ = m ± sin(α/2) u, so the face turned more to the eye v has
            // n·v = m·v + sin(α/2)|u·v|, u = m × (b − a) normalized.
            vec3 across = cross(n, mat3(cam.view) * (t1.xyz - t0.xyz));  // b − a, without the camera's offset
            float turned = sqrt(max(0.0, 1.0 - dot(n, n))), toward = dot(n, -normalize(mid));
            if (dot(across, across) > 1e-20) toward += turned * abs(dot(across, normalize(mid))) / length(across);
            visible = visible && toward > -FACING_SLACK;
        }
        flags = visible ? SEG_VISIBLE : SEG_HIDDEN;
        raw = (keep ? SEG_RAW_SHOWN : 0u) | (visible ? SEG_RAW_VISIBLE : 0u);
        keep = keep && (visible || lineStyle.options.y != 0.0);
        width = lineWidth(kind, visible);
    } else {
        // Tested a little beyond the contour in the image, on the side its normal points to (its own surface lies
        // on the other): near the outline the splat disks of that surface stand almost edge-on and reach out in
        // front of the contour, while beyond it lies only what the contour passes in front of, or what hides it.
        vec4 nearer = project(mid - normalize(mid) * (2.0 * cam.params.x));
        vec2 pm = toPixels(nearer);
        vec2 outward = toPixels(project(mid + n * (1e-3 * -mid.z))) - toPixels(project(mid));
        vec2 beyond = pm + (length(outward) > 1e-6 ? outward / length(outward) : vec2(0.0)) * 3.0;
        // A piece its own surface hides (concave along the view) is hidden, whatever the depth test says.
        bool visible = nearer.z / nearer.w <= uintBitsToFloat(depthAt(beyond)) && (kind & KIND_OCCLUDED) == 0u;
        flags = visible ? SEG_VISIBLE : SEG_HIDDEN;
        raw = (keep ? SEG_RAW_SHOWN : 0u) | (visible ? SEG_RAW_VISIBLE : 0u);
        keep = keep && (visible || lineStyle.options.y != 0.0);
        // Surface on both sides in the image: the contour lies in front of more surface (interior).
        vec2 dir = pb - pa;
        vec2 side = length(dir) > 1e-6 ? vec2(-dir.y, dir.x) / length(dir) : vec2(1.0, 0.0);
        float reach = 0.5 * lineStyle.widths.x + lineStyle.widths.w + 2.0 * cam.params.y;
        if (visible && depthAt(pm + side * reach) != FAR_DEPTH && depthAt(pm - side * reach) != FAR_DEPTH)
            flags |= SEG_INTERIOR;
        width = lineWidth(kind, visible);
    }
    DrawSegment s;
    s.ends = vec4(pa, pb);
    s.widths = 0.5 * width * (feature ? vec2(1.0) : vec2(t0.w, t1.w));
    s.flags = keep ? flags : 0u;
    s.segment = index | raw;
    if (i < cam.counts.x) drawList.list[i] = s;
    if (i == 0u) drawList.draw.x = 6u * cam.counts.x;
}
