#version 460
#extension GL_GOOGLE_include_directive : require
// The screen spacing of the toned dots (engine/draw/screen_spacing.h explains it; screen_spacing.cpp is the CPU twin,
// decision for decision): a grid over the target with cells of side c, small enough (c ≤ r/√2 for every radius
// r) that a cell holds at most one accepted dot. Each round, every cell elects its open dot of the lowest key
// (then point index) in three passes of atomics (cam.counts.w: PASS_CLAIM_KEY, _POINT, _DOT), and PASS_DECIDE
// accepts each elected dot that no elected dot of a lower key lies within the smaller of their two radii of;
// PASS_CLAIM_KEY first rejects the open dots that an earlier round's accepted dot lies that close to. Two dots
// accepted in one round are never that close (one blocks the other), and no pass reads what it writes, so the
// outcome does not depend on the order the invocations run in. Only the first round's PASS_CLAIM_KEY visits every
// dot: it and each later one list the dots that stay open (SpaceOpen), and the round's other passes and the next
// round's PASS_CLAIM_KEY visit that list alone (after two rounds, a few percent of the dots).
#include "draw/render_common.glsl"

layout(local_size_x = GROUP_SIZE) in;

// Four planes of `cells` words: the lowest key, the lowest point index with it, the elected dot (the list index),
// the accepted dot; 0xFFFFFFFF where none. After the rounds, the relaxation keeps each accepted dot's displacement
// (packSnorm2x16 of it over SPACE_RELAX_MAX radii) in the first two planes in turn, at the cell of its pixel: the
// pixels stay until PASS_PLACE, so each step reads one plane and writes the other. The third plane then holds the
// accepted dots' list (PASS_LIST): a uvec4 header (workgroups, 1, 1, dots), the relaxation's indirect dispatch,
// then their indices (at most about 0.64 of the cells, more along the target's border: each holds alone a disk of
// half a radius, over 0.7 of a cell's side), and at its end a word a block of SPACE_BLOCK² cells (a 16th of them), the mask of those that hold one.
layout(std430, binding = RENDER_SPACE_GRID) buffer SpaceGrid { uint grid[]; };

// Two lists of open dots (the list indices), one a round in turn, each a uvec4 header (workgroups, 1, 1, dots: the
// next passes' indirect dispatch) then up to one word a point of the set.
layout(std430, binding = RENDER_SPACE_OPEN) buffer SpaceOpen { uint open[]; };

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

// A dot's displacement, stored in `word` over SPACE_RELAX_MAX radii.
vec2 displacement(uint word, float radius) {
    precise vec2 v = unpackSnorm2x16(word) * (SPACE_RELAX_MAX * radius);
    return v;
}

// The vector v, shortened to at most `most` long.
vec2 atMost(vec2 v, float most) {
    precise float l2 = v.x * v.x + v.y * v.y;
    if (l2 <= most * most) return v;
    precise vec2 shorter = v * (most / sqrt(l2));
    return shorter;
}

// The blocks of SPACE_BLOCK² cells: the relaxation's masks of the cells that hold an accepted dot, at the end of the
// third plane.
uint blocksAcross(ivec2 size) { return (uint(size.x) + SPACE_BLOCK - 1u) / SPACE_BLOCK; }

uint blocksOf(ivec2 size) { return blocksAcross(size) * ((uint(size.y) + SPACE_BLOCK - 1u) / SPACE_BLOCK); }

// Where the blocks' masks begin, and the list's room before them.
uint masksAt(ivec2 size, uint cells) { return 3u * cells - blocksOf(size); }
uint listRoom(ivec2 size, uint cells) { return cells - blocksOf(size) - SPACE_LIST_HEADER; }

// The open list of round r's parity: its header (workgroups, 1, 1, dots) and its room.
uint openAt(uint r) { return (r & 1u) * (uint(open.length()) / 2u); }
uint openRoom() { return uint(open.length()) / 2u - SPACE_LIST_HEADER; }

// PASS_RELAX, step `step`: the accepted dot d's displacement after one more step, from the plane of the last.
void relax(Dot d, ivec2 c, uint cell, ivec2 size, uint cells, uint step) {
    uint from = (step & 1u) * cells, to = cells - from;
    precise vec2 moved = displacement(grid[from + cell], d.radius);
    precise vec2 p = d.pixel + moved;
    precise float reach = SPACE_RELAX_REACH * d.radius;
    precise float reach2 = reach * reach;
    precise float searchCells = reach * style.options.w;
    int search = int(ceil(searchCells));
    precise vec2 push = vec2(0.0);
    precise vec2 around = vec2(0.0);
    uint neighbours = 0u;
    // The room to the nearest neighbour: how far past SPACE_RELAX_FLOOR of their smaller radius they lie.
    precise float room = 2.0 * SPACE_RELAX_STEP_MAX * d.radius;
    // The blocks in reach, and in each the cells that hold an accepted dot, in the order of their bits.
    int block = int(SPACE_BLOCK);
    uint blocksX = blocksAcross(size);
    uint masks = masksAt(size, cells);
    for (int by = max(c.y - search, 0) / block; by <= min(c.y + search, size.y - 1) / block; ++by)
        for (int bx = max(c.x - search, 0) / block; bx <= min(c.x + search, size.x - 1) / block; ++bx)
            for (uint mask = grid[masks + uint(by) * blocksX + uint(bx)]; mask != 0u; mask &= mask - 1u) {
                int bit = findLSB(mask);
                uint n = uint(by * block + bit / block) * uint(size.x) + uint(bx * block + bit % block);
                if (n == cell) continue;
                Dot e = list.dots[grid[3u * cells + n]];
                precise vec2 q = e.pixel + displacement(grid[from + n], e.radius);
                precise vec2 delta = p - q;
                precise float d2 = delta.x * delta.x + delta.y * delta.y;
                if (d2 >= reach2) continue;
                push += delta * (reach2 - d2);
                around += delta;
                ++neighbours;
                precise float apart = sqrt(d2) - SPACE_RELAX_FLOOR * min(d.radius, e.radius);
                room = min(room, apart);
            }
    precise float edge = SPACE_RELAX_EDGE * reach * float(neighbours);
    precise float off2 = around.x * around.x + around.y * around.y;
    if (neighbours >= 3u && off2 <= edge * edge) {
        // A step of at most half the room: two dots that step towards each other keep SPACE_RELAX_FLOOR of the
        // spacing's radius between them.
        precise vec2 pushed = push * (SPACE_RELAX_STEP / reach2);
        precise vec2 next = moved + atMost(pushed, min(SPACE_RELAX_STEP_MAX * d.radius, 0.5 * max(room, 0.0)));
        precise float most = SPACE_RELAX_MAX * d.radius;
        precise float next2 = next.x * next.x + next.y * next.y;
        if (next2 <= most * most) moved = next;
    }
    grid[to + cell] = packSnorm2x16(moved / (SPACE_RELAX_MAX * d.radius));
}

void main() {
    uint pass = cam.counts.w & 0xFFu;
    uint round = cam.counts.w >> 8u;  // PASS_CLAIM_* and PASS_DECIDE
    ivec2 size = gridSize();
    uint cells = uint(size.x) * uint(size.y);
    uint i = gl_GlobalInvocationID.x;
    if (pass == PASS_RELAX || pass == PASS_PLACE) {
        // Over the accepted dots' list (PASS_LIST), not every dot: on a CPU driver a pass over all would run the
        // neighbour search for every batch of lanes that holds one accepted dot.
        // The count may pass the list's room (see PASS_LIST's guard): only the listed dots are visited.
        if (i >= min(grid[2u * cells + 3u], listRoom(size, cells))) return;
        i = grid[2u * cells + SPACE_LIST_HEADER + i];
    } else if (pass >= PASS_CLAIM_KEY && pass <= PASS_DECIDE && (pass != PASS_CLAIM_KEY || round > 0u)) {
        // Over the dots this round's PASS_CLAIM_KEY left open, or the last round's for PASS_CLAIM_KEY.
        uint at = openAt(pass == PASS_CLAIM_KEY ? round - 1u : round);
        if (i >= min(open[at + 3u], openRoom())) return;
        i = open[at + SPACE_LIST_HEADER + i];
    } else if (i >= list.dispatch.w) {
        return;
    }
    Dot d = list.dots[i];
    ivec2 c = cellOf(d.pixel, size);
    uint cell = uint(c.y) * uint(size.x) + uint(c.x);
    if (pass == PASS_LIST) {
        if (d.state != SPACE_ACCEPTED) return;
        uint slot = atomicAdd(grid[2u * cells + 3u], 1u);
        // Past the list's room the dot is not moved (and no other sees it). Not seen on any target: about 0.64 of
        // the cells at most (see SpaceGrid), though a grid one cell wide could pack 0.87 against its room of 0.75.
        if (slot >= listRoom(size, cells)) return;
        grid[2u * cells + SPACE_LIST_HEADER + slot] = i;
        // The first dot of each workgroup's worth raises the workgroups (slots are dense from 0).
        if (slot % GROUP_SIZE == 0u) atomicMax(grid[2u * cells], slot / GROUP_SIZE + 1u);
        uint block = uint(c.y) / SPACE_BLOCK * blocksAcross(size) + uint(c.x) / SPACE_BLOCK;
        atomicOr(grid[masksAt(size, cells) + block],
                 1u << (uint(c.y) % SPACE_BLOCK * SPACE_BLOCK + uint(c.x) % SPACE_BLOCK));
        return;
    }
    if (pass == PASS_RELAX) {
        relax(d, c, cell, size, cells, cam.counts.w >> 8u);
        return;
    }
    if (pass == PASS_PLACE) {
        list.dots[i].pixel = d.pixel + displacement(grid[(SPACE_RELAX_ROUNDS & 1u) * cells + cell], d.radius);
        return;
    }
    if (d.state != SPACE_OPEN) return;
    uint point = d.cls >> 4u;
    precise float reachCells = d.radius * style.options.w;
    int reach = int(ceil(reachCells));
    if (pass == PASS_CLAIM_KEY) {
        // Rejected when a dot accepted in an earlier round lies within reach (none before the first), else a
        // candidate for its cell, and listed for this round's passes.
        bool covered = false;
        for (int y = max(c.y - reach, 0); y <= min(c.y + reach, size.y - 1) && !covered && round > 0u; ++y)
            for (int x = max(c.x - reach, 0); x <= min(c.x + reach, size.x - 1) && !covered; ++x) {
                uint a = grid[3u * cells + uint(y) * uint(size.x) + uint(x)];
                if (a != NONE && conflict(d, list.dots[a])) covered = true;
            }
        if (covered) {
            list.dots[i].state = SPACE_REJECTED;
            return;
        }
        atomicMin(grid[cell], d.key);
        uint at = openAt(round);
        uint slot = atomicAdd(open[at + 3u], 1u);
        if (slot >= openRoom()) return;  // never: a list has a word for every point of the set
        open[at + SPACE_LIST_HEADER + slot] = i;
        if (slot % GROUP_SIZE == 0u) atomicMax(open[at], slot / GROUP_SIZE + 1u);
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
