#version 460
#extension GL_GOOGLE_include_directive : require
// The contour's seeds (docs/lines.md). The contour is where n·v changes sign (v towards the eye), so it runs
// between the drawn points that face the eye and those that face away, wherever the points lie: a seed is put
// between the nearest such pair around each cell. Three passes over a hashed grid of cells:
// - CONTOUR_PASS_CELLS (per point): each cell keeps the least n·v of its points facing the eye, and the least
//   |n·v| of those facing away (non-negative floats order as their bits);
// - CONTOUR_PASS_PICK (per point): the point that has it (the least index among equals, so that the choice does
//   not depend on the device's schedule) wins its side of the cell;
// - CONTOUR_PASS_PAIR (per slot): a cell's winner facing the eye pairs with the nearest winner facing away in
//   the 27 cells around it, and the seed is where n·v, interpolated along the pair, is 0. Listed for
//   contour_trace.comp, which projects the seeds onto the contour.
// Unlike a band |n·v| < ε, this finds the contour where the normal turns faster than the points are spaced (the
// rims of thin parts seen edge on), and gives one seed per cell along the whole curve.
#include "lines/contour_common.glsl"

float facing(Point p) { return dot(p.normal, normalize(pc.eye.xyz - p.position)); }

void pair(uint s) {
    uint base = CONTOUR_SEED_SLOT * s, key = seedTable[base], a = seedTable[base + 3u];
    if (key == CONTOUR_NONE || a == CONTOUR_NONE) return;
    Point p = samples[a];
    ivec3 c = contourCell(p.position);
    float best = 2.0 * pc.sizes.x;
    uint partner = CONTOUR_NONE;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                uint t = seedSlot(contourCellKey(c + ivec3(dx, dy, dz)), false);
                if (t == CONTOUR_NONE) continue;
                uint b = seedTable[CONTOUR_SEED_SLOT * t + 4u];
                if (b == CONTOUR_NONE) continue;
                float d = distance(p.position, samples[b].position);
                if (d < best) {
                    best = d;
                    partner = b;
                }
            }
    if (partner == CONTOUR_NONE) return;
    Point q = samples[partner];
    float fp = facing(p), fq = -facing(q);  // both ≥ 0
    vec3 x = mix(p.position, q.position, fp / max(fp + fq, 1e-20));
    uint at = atomicAdd(counters.listed, 1u);
    seedList[at] = vec4(x, 0.0);
    atomicMax(counters.project.x, at / pc.shape.x + 1u);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (pc.counts.w == CONTOUR_PASS_PAIR) {
        if (i < pc.counts.y) pair(i);
        return;
    }
    if (i >= pc.counts.x) return;
    Point p = samples[i];
    float f = facing(p);
    uint side = f >= 0.0 ? 0u : 1u;
    bool cells = pc.counts.w == CONTOUR_PASS_CELLS;
    uint s = seedSlot(contourCellKey(contourCell(p.position)), cells);
    if (s == CONTOUR_NONE) {
        if (cells) atomicAdd(counters.lost, 1u);
        return;
    }
    uint base = CONTOUR_SEED_SLOT * s;
    if (cells)
        atomicMin(seedTable[base + 1u + side], floatBitsToUint(abs(f)));
    else if (seedTable[base + 1u + side] == floatBitsToUint(abs(f)))
        atomicMin(seedTable[base + 3u + side], i);
}
