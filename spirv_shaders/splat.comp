#version 460
#extension GL_GOOGLE_include_directive : require
// Visibility splatting (ALGORITHM.md §6) as a compute pass: each point is a disk in its tangent plane; the
// view ray of every depth cell the disk may cover is cast onto the disk's plane, and the plane's depth, pushed
// back by one radius, goes into the cell with atomicMin. Depth cells are half the target's resolution: dots are
// tested against surfaces, and surfaces vary slowly.
#include "render_common.glsl"

layout(local_size_x = 64) in;

const int MAX_CELLS = 9;  // a disk spans at most this many cells a side; larger disks are sampled sparsely

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cam.counts.x) return;
    Point p = fetchPoint(cam.counts.z + i);
    vec3 c = (cam.view * vec4(p.position, 1.0)).xyz;
    vec3 n = mat3(cam.view) * p.normal;
    // Disks facing away lie behind the front surface of a closed shape; keep a margin for edge-on ones.
    if (-c.z <= 1e-6 || dot(n, -normalize(c)) < -0.2) return;
    vec4 clip = project(c);
    vec2 grid = cam.viewport.zw;
    vec2 center = (clip.xy / clip.w * 0.5 + 0.5) * grid;
    float radius = cam.splat.x * abs(cam.projection.y) * 0.5 * grid.y / (-c.z);  // in cells
    // Cells whose centres the disk's screen footprint may reach (the ray test below is exact).
    ivec2 lo = ivec2(floor(center - radius - 0.5)), hi = ivec2(floor(center + radius - 0.5)) + 1;
    int step = max(1, (max(hi.x - lo.x, hi.y - lo.y) + MAX_CELLS) / MAX_CELLS);
    float planeD = dot(c, n);
    for (int y = lo.y; y <= hi.y; y += step) {
        for (int x = lo.x; x <= hi.x; x += step) {
            if (x < 0 || y < 0 || x >= int(grid.x) || y >= int(grid.y)) continue;
            vec2 ndc = (vec2(x, y) + 0.5) / grid * 2.0 - 1.0;
            vec3 ray = vec3(ndc.x / cam.projection.x, ndc.y / cam.projection.y, -1.0);
            float denom = dot(ray, n);
            vec3 hit;
            if (abs(denom) > 1e-6) {
                hit = ray * (planeD / denom);
                if (distance(hit, c) > cam.splat.x) continue;
            } else if (ivec2(x, y) == ivec2(floor(center))) {
                hit = c;  // edge-on: the centre cell still gets the point's own depth
            } else {
                continue;
            }
            hit += normalize(hit) * cam.splat.y;
            vec4 h = project(hit);
            atomicMin(depth[y * int(grid.x) + x], floatBitsToUint(max(h.z / h.w, 0.0)));
        }
    }
}
