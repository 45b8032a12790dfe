#version 460
#extension GL_GOOGLE_include_directive : require
// The screen spacing of the toned dots (engine/draw/screen_spacing.h explains it; screen_spacing.cpp is the CPU twin,
// decision for decision): a grid over the target with cells of side c, small enough (c ≤ r/√2 for every radius
// r) that a cell holds at most one accepted dot. Each round, every cell elects its open dot of the lowest key
// (then point index) in three passes of atomics (cam.counts.w: PASS_CLAIM_KEY, _POINT, _DOT), and PASS_DECIDE
// accepts each elected dot that no elected dot of a lower key lies within the smaller of their two radii of;
// PASS_CLAIM_KEY first rejects the open dots that an earlier round's accepted dot lies that close to. Two dots
// accepted in one round are never that close (one blocks the other), and no pass reads what it writes, so the
// outcome does not depend on the order the invocations run in.
#include "draw/render_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

// Four planes of `cells` words: the lowest key, the lowest point index with it, the elected dot (the list index),
// the accepted dot; 0xFFFFFFFF where none.
layout(std430, binding = RENDER_SPACE_GRID) buffer SpaceGrid { uint grid[]; };

const uint NONE = 0xFFFFFFFFu;

ivec2 gridSize() { return ivec2(ceil(cam.viewport.xy * style.options.w)); }

ivec2 cellOf(vec2 pixel, ivec2 size) {
    precise vec2 x = pixel * style.options.w;
    return clamp(ivec2(floor(x)), ivec2(0), size - 1);
}

bool before(uint keyA, uint pointA, uint keyB, uint pointB) {
    return keyA < keyB || (keyA == keyB && pointA < pointB);
}

// Whether two dots are closer than the smaller of their radii.
bool conflict(Dot a, Dot b) {
    precise float dx = a.pixel.x - b.pixel.x;
    precise float dy = a.pixel.y - b.pixel.y;
    precise float d2 = dx * dx + dy * dy;
    float r = min(a.radius, b.radius);
    precise float r2 = r * r;
    return d2 < r2;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= list.dispatch.w) return;
    Dot d = list.dots[i];
    uint pass = cam.counts.w;
    if (d.state != SPACE_OPEN) return;
    ivec2 size = gridSize();
    uint cells = uint(size.x) * uint(size.y);
    ivec2 c = cellOf(d.pixel, size);
    uint cell = uint(c.y) * uint(size.x) + uint(c.x);
    uint point = d.cls >> 4u;
    precise float reachCells = d.radius * style.options.w;
    int reach = int(ceil(reachCells));
    if (pass == PASS_CLAIM_KEY) {
        // Rejected when a dot accepted in an earlier round lies within reach, else a candidate for its cell.
        bool covered = false;
        for (int y = max(c.y - reach, 0); y <= min(c.y + reach, size.y - 1) && !covered; ++y)
            for (int x = max(c.x - reach, 0); x <= min(c.x + reach, size.x - 1) && !covered; ++x) {
                uint a = grid[3u * cells + uint(y) * uint(size.x) + uint(x)];
                if (a != NONE && conflict(d, list.dots[a])) covered = true;
            }
        if (covered)
            list.dots[i].state = SPACE_REJECTED;
        else
            atomicMin(grid[cell], d.key);
    } else if (pass == PASS_CLAIM_POINT) {
        if (grid[cell] == d.key) atomicMin(grid[cells + cell], point);
    } else if (pass == PASS_CLAIM_DOT) {
        if (grid[cell] == d.key && grid[cells + cell] == point) grid[2u * cells + cell] = i;
    } else if (grid[2u * cells + cell] == i) {
        // Elected: accepted unless another cell's elected dot of a lower key is within reach.
        bool blocked = false;
        for (int y = max(c.y - reach, 0); y <= min(c.y + reach, size.y - 1) && !blocked; ++y)
            for (int x = max(c.x - reach, 0); x <= min(c.x + reach, size.x - 1) && !blocked; ++x) {
                uint n = uint(y) * uint(size.x) + uint(x);
                if (n == cell || grid[n] == NONE) continue;
                if (before(grid[n], grid[cells + n], d.key, point) && conflict(d, list.dots[grid[2u * cells + n]]))
                    blocked = true;
            }
        if (!blocked) {
            list.dots[i].state = SPACE_ACCEPTED;
            grid[3u * cells + cell] = i;
        }
    }
}
