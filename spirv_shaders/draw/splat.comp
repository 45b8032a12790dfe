#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
// Once per point and frame, the two things that need every point:
// - visibility splatting (ALGORITHM.md §6): each front-facing point is a disk in its tangent plane; the view
//   ray of every depth cell the disk may cover is cast onto the disk's plane, and the plane's depth, pushed
//   back by one radius, goes into the cell with atomicMin. Depth cells are half the target's resolution: dots
//   are tested against surfaces, and surfaces vary slowly.
// - the dot the point may draw: its class (report §5), its tone (Brazil et al. 2011) and the frustum decide;
//   the dots that pass go to the list that stamp.comp tests against the finished depth.
#include "draw/render_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

// A disk is tested cell by cell up to this many cells a side. A larger one (a sparse set drawn large, a view zoomed
// in) is sampled every `step` cells, and each sample inside the disk writes its depth to its whole step × step block:
// sampled alone, the cells between were left without the disk's depth, and what lies behind showed through the
// holes (a cube's back edges through its faces, with 2 levels at 1024²). With CAMERA_SPARSE_SPLATS (direction
// sampling) a sample writes its own cell only, beyond MAX_SPARSE_CELLS a side.
const int MAX_CELLS = 24, MAX_SPARSE_CELLS = 9;

// `back`: the disk of an open surface's back (CAMERA_TWO_SIDED), which marks the cells it is nearest in with the
// depth's lowest bit (one ulp): stamp.comp hides a back dot behind a front-facing disk more strictly.
void splat(vec3 c, vec3 n, bool back) {
    vec4 clip = project(c);
    vec2 grid = cam.viewport.zw;
    vec2 center = (clip.xy / clip.w * 0.5 + 0.5) * grid;
    // The disk's screen footprint lies within this many cells of its centre's projection, a side: a disk point
    // c + u (|u| ≤ R) lands f·(u.x·z + c.x·u.z) / (z·(z − u.z)) cells away in x, z = −c.z, f cells per unit
    // (likewise in y). The cells whose centres it may reach are tested, exactly.
    float z = -c.z;
    vec2 f = abs(cam.projection.xy) * 0.5 * grid;
    bool sparse = (cam.counts.y & CAMERA_SPARSE_SPLATS) != 0u;
    // Filled disks also take the cells their ellipse only crosses (below): one cell more each way, and a cell's
    // half side at the disk's depth, in the model's units (0: direction sampling's sparse disks keep to their
    // rim).
    vec2 radius = min(f * cam.splat.x * (1.0 + abs(c.xy) / z) / max(z - cam.splat.x, 1e-6) + (sparse ? 0.0 : 1.0),
                      grid);
    float halfCell = sparse ? 0.0 : 0.5 * z / min(f.x, f.y);
    ivec2 lo = max(ivec2(ceil(center - radius - 0.5)), ivec2(0));
    ivec2 hi = min(ivec2(floor(center + radius - 0.5)), ivec2(grid) - 1);
    int most = sparse ? MAX_SPARSE_CELLS : MAX_CELLS;
    int step = max(1, (max(hi.x - lo.x, hi.y - lo.y) + most) / most), block = sparse ? 1 : step;
    float planeD = dot(c, n);
    for (int y = lo.y; y <= hi.y; y += step) {
        for (int x = lo.x; x <= hi.x; x += step) {
            // The block's middle cell stands for it.
            vec2 ndc = (vec2(min(x + block / 2, hi.x), min(y + block / 2, hi.y)) + 0.5) / grid * 2.0 - 1.0;
            vec3 ray = vec3(ndc.x / cam.projection.x, ndc.y / cam.projection.y, -1.0);
            float denom = dot(ray, n);
            vec3 hit;
            if (abs(denom) > 1e-6) {
                hit = ray * (planeD / denom);
                // Conservatively: a cell whose centre's ray meets the plane within half a cell of the disk, measured
                // across the ray: in the plane that is 1/|cos| times as far along the direction the ray tilts
                // (at most half a radius), half a cell across it. A disk seen nearly edge-on is an ellipse thinner
                // than a cell, whose cells' centres mostly miss it: there the surface behind showed through (ray
                // casting: 90 of the torus's 104 dots drawn though occluded, in the band where its tube turns
                // away from the eye).
                vec3 toward = normalize(ray);
                vec3 tilt = toward - dot(toward, n) * n;
                float tiltLength = length(tilt);
                vec3 offset = hit - c;
                float alongTilt = tiltLength > 1e-6 ? abs(dot(offset, tilt / tiltLength)) : 0.0;
                float acrossTilt = sqrt(max(dot(offset, offset) - alongTilt * alongTilt, 0.0));
                float slackAlong = min(halfCell / max(abs(dot(toward, n)), 0.05), 0.5 * cam.splat.x);
                vec2 outside = max(vec2(alongTilt - slackAlong, acrossTilt - halfCell), vec2(0.0));
                if (dot(outside, outside) > cam.splat.x * cam.splat.x) continue;
            } else if (ivec2(x, y) == ivec2(floor(center))) {
                hit = c;  // edge-on: the centre cell still gets the point's own depth
            } else {
                continue;
            }
            // Pushed back by the radius, and (filled disks) by as far as a sphere of the disk's radius curves away
            // from the disk at the hit, seen along the ray (d² / 2R over |cos| of the ray to the normal, |cos| taken
            // as at least ½: at most one radius more at the rim): at grazing angles a flat disk stands in front of
            // its own curved surface. Measured against ray casting (docs/algorithm.md §4, item 1).
            vec3 along = normalize(hit);
            float curve = sparse ? 0.0 : dot(hit - c, hit - c) / (2.0 * cam.splat.x) / max(abs(dot(along, n)), 0.5);
            hit += along * (cam.splat.y + curve);
            vec4 h = project(hit);
            uint cellDepth = floatBitsToUint(max(h.z / h.w, 0.0));
            if ((cam.counts.y & CAMERA_TWO_SIDED) != 0u) cellDepth = cellDepth & ~1u | (back ? 1u : 0u);
            for (int by = y; by < min(y + block, hi.y + 1); ++by)
                for (int bx = x; bx < min(x + block, hi.x + 1); ++bx) atomicMin(depth[by * int(grid.x) + bx], cellDepth);
        }
    }
}

// A silhouette dot's reach along the outline, pixels (SILHOUETTE_REACH; stamp.comp's PASS_REACH makes it the
// stroke): across the motion of c + εn on the screen (the pixel x of c is P00·x / −z, so d/dε ∝ P00·(n.x·(−z) +
// x·n.z), likewise y). Direction sampling's dots lie on lines already, and its splat radius is the coarse spacing:
// round.
vec2 silhouetteReach(vec3 c, vec3 n) {
    if ((cam.counts.y & CAMERA_SPARSE_SPLATS) != 0u) return vec2(0.0);
    float z = -c.z;
    vec2 across = cam.projection.xy * (n.xy * z + c.xy * n.z) * cam.viewport.xy;
    float length2 = dot(across, across);
    if (!(length2 > 0.0)) return vec2(0.0);  // the normal along the view ray: no outline direction
    float reach = min(SILHOUETTE_REACH * cam.splat.x * abs(cam.projection.x) * 0.5 * cam.viewport.x / z,
                      SILHOUETTE_REACH_MAX * style.size.x);
    return vec2(-across.y, across.x) * (inversesqrt(length2) * reach);
}

// The silhouette test's τ at a point c (view space) of unit normal `stored` (model space, as shape.comp's frame)
// whose shape operator is `shape`: the style's, or √(2 κ_r w) where that is less, κ_r the radial curvature (along
// the view direction's tangential part r̂) and w SILHOUETTE_BAND dot diameters at the point's depth, so that the
// band |n·v| < τ, τ² / (2 κ_r) wide on the screen, is at most w wide (shared/render.h).
float silhouetteTau(vec3 c, vec3 stored, vec4 shape) {
    float tau = style.size.w;
    if (shape.w == 0.0 || tau == 0.0) return tau;
    vec3 v = transpose(mat3(cam.view)) * -normalize(c);  // towards the eye, in the model's frame
    vec3 r = v - dot(v, stored) * stored;
    float r2 = dot(r, r);
    if (!(r2 > 1e-12)) return tau;  // the eye along the normal: no outline near
    vec3 t1, t2;
    tangentFrame(stored, t1, t2);
    float x = dot(r, t1), y = dot(r, t2);
    float kr = abs(x * x * shape.x + 2.0 * x * y * shape.y + y * y * shape.z) / r2;
    float w = SILHOUETTE_BAND * style.size.x * -c.z / (abs(cam.projection.x) * 0.5 * cam.viewport.x);
    return min(tau, sqrt(2.0 * kr * w));
}

// Whether the point's dot may show — its class is not BACK, its tone keeps it, it is in the frustum — and
// that dot.
bool selectDot(Point p, uint index, vec3 c, vec3 n, float nv, bool back, float tau, out Dot d) {
    uint cls = classify(nv, tau);
    d.cls = cls | (back ? DOT_BACK_SIDE : 0u) | (index << 3u);
    d.radius = 0.0;
    d.key = floatBitsToUint(p.tone);
    d.state = SPACE_FIXED;
    d.scale = 1.0;
    d.along = vec2(0.0);
    if (cls == BACK) return false;
    if (cls == FRONT && style.light.w > 0.0) {
        // Drawn when its rank (or, for the report's look, its fixed random value) is below the darkness: the
        // stipples of a tone are a prefix of the ranking, evenly spaced, a darker tone only adds dots, and a dot
        // keeps its state while the light on it does not change (a light fixed to the model: as the camera moves).
        float lit = max(0.0, dot(style.options.x != 0.0 ? p.normal : n, style.light.xyz));
        float darkness = (style.tone.y + pow(1.0 - lit, style.light.w)) * style.tone.x;
        float threshold = darkness * cam.splat.z;
        if (style.options.z > 0.0 && (cam.counts.y & CAMERA_SPACED) != 0u) {
            // Screen spacing (spacing.comp): the candidates of a tone, about SPACE_SUPPLY times the dots it asks
            // for, on the page, where the surface turns away (n·v) and recedes (depth²) they crowd on the screen.
            threshold *= nv * (c.z * c.z) / cam.splat.w;
            // Where the point set gives fewer than SPACE_SUPPLY_KEPT candidates a dot (threshold past
            // SPACE_SUPPLY / SPACE_SUPPLY_KEPT), the dots are spaced for `fewer` times less density, each larger to
            // carry `fewer` times the ink, up to SPACE_MAX_SCALE in diameter (past that the dots are not thinned
            // further: the tone's ink goes before its evenness).
            float fewer = clamp(threshold * (SPACE_SUPPLY_KEPT / SPACE_SUPPLY), 1.0, SPACE_MAX_SCALE * SPACE_MAX_SCALE);
            d.radius = min(style.options.z * sqrt(fewer / max(darkness, 1e-3)), SPACE_MAX_CELLS / style.options.w);
            d.scale = sqrt(fewer);
            d.state = SPACE_OPEN;
        }
        if (p.tone >= threshold) return false;
    }
    vec4 clip = project(c);
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0))) || ndc.z > 1.0) return false;
    d.pixel = (ndc.xy * 0.5 + 0.5) * cam.viewport.xy;
    d.z = ndc.z;
    if (cls == SILHOUETTE) {
        // Near the outline the disks are edge-on and their depths jump from cell to cell: a silhouette dot is
        // tested two push-backs nearer the camera, so that its own surface does not hide it in one frame and
        // show it in the next.
        vec4 nearer = project(c - normalize(c) * (2.0 * cam.splat.y));
        d.z = nearer.z / nearer.w;
        d.along = silhouetteReach(c, n);
    }
    return true;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint k = min(i, cam.counts.x - 1u);  // the draw's k-th point
    Point p = fetchPoint(cam.counts.z + k);
    vec3 c = (cam.view * vec4(p.position, 1.0)).xyz;
    vec3 n = mat3(cam.view) * p.normal;
    float nv = dot(n, -normalize(c));
    bool inFront = i < cam.counts.x && -c.z > 1e-6;
    float tau = inFront ? silhouetteTau(c, p.normal, texelFetch(shapeTexels, int(k))) : style.size.w;
    // Disks facing away lie behind the front surface of a closed shape; keep a margin for edge-on ones. An open
    // surface's (CAMERA_TWO_SIDED) are its back, seen through its openings: splatted, and its points drawn as the
    // other side, facing the eye (lit and classified so); those that would be BACK are tested as such (stamp.comp).
    bool twoSided = (cam.counts.y & CAMERA_TWO_SIDED) != 0u;
    bool back = twoSided && nv <= -tau;  // what one-sided drawing classifies BACK
    if (twoSided && nv < 0.0) {
        n = -n;
        nv = -nv;
        p.normal = -p.normal;
    }
    if (inFront && cam.splat.y > 0.0 && nv >= -0.2) splat(c, n, back);

    Dot d;
    bool selected = inFront && style.options.y == 0.0 && selectDot(p, i, c, n, nv, back, tau, d);
    // Appended a subgroup at a time: one atomic for the slots, one for the dispatch size.
    uvec4 ballot = subgroupBallot(selected);
    uint count = subgroupBallotBitCount(ballot), first = 0u;
    if (subgroupElect() && count > 0u) {
        first = atomicAdd(list.dispatch.w, count);
        atomicMax(list.dispatch.x, (first + count + GROUP_SIZE - 1u) / GROUP_SIZE);
    }
    first = subgroupBroadcastFirst(first);
    if (selected) list.dots[first + subgroupBallotExclusiveBitCount(ballot)] = d;
}
