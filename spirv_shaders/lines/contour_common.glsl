// What the contour passes share (engine/lines/contour_device.cpp, docs/lines.md): the bindings, the two hashed
// grids (seeds by cell, nodes by cell) and the push constants.
#ifndef CONTOUR_COMMON_GLSL
#define CONTOUR_COMMON_GLSL

#include "shared/contour.h"
#include "shared/refine.h"  // Point

layout(local_size_x = CONTOUR_GROUP_SIZE) in;

layout(std430, binding = CONTOUR_SAMPLES) readonly buffer Samples { Point samples[]; };
layout(std430, binding = CONTOUR_SEEDS) buffer SeedTable { uint seedTable[]; };
layout(std430, binding = CONTOUR_NODES) buffer Nodes { ContourNode nodes[]; };
layout(std430, binding = CONTOUR_GRID) buffer NodeGrid { uint nodeGrid[]; };
layout(std430, binding = CONTOUR_VERTICES) writeonly buffer Vertices { ContourVertex vertices[]; };
layout(std430, binding = CONTOUR_COUNTERS) buffer Counters { ContourCounters counters; };
layout(std430, binding = CONTOUR_LIST) buffer List { vec4 seedList[]; };

layout(push_constant) uniform Params { ContourParams pc; };

// A grid cell's key: ten bits an axis (the cells wrap every 1024, far beyond a normalized model), never NONE.
uint contourCellKey(ivec3 c) { return uint(c.x & 1023) | uint(c.y & 1023) << 10 | uint(c.z & 1023) << 20; }
ivec3 contourCell(vec3 x) { return ivec3(floor(x / pc.sizes.x)); }

uint contourHash(uint key) {
    key ^= key >> 16;
    key *= 0x7feb352du;
    key ^= key >> 15;
    key *= 0x846ca68bu;
    return key ^ (key >> 16);
}

INK_CONST uint CONTOUR_PROBES = 64u;

// The seed table's slot of a cell (claimed when `claim`), or NONE.
uint seedSlot(uint key, bool claim) {
    uint mask = pc.counts.y - 1u, s = contourHash(key) & mask;
    for (uint probe = 0u; probe < CONTOUR_PROBES; ++probe, s = (s + 1u) & mask) {
        uint k = seedTable[CONTOUR_SEED_SLOT * s];
        if (k == key) return s;
        if (k != CONTOUR_NONE) continue;
        if (!claim) return CONTOUR_NONE;
        k = atomicCompSwap(seedTable[CONTOUR_SEED_SLOT * s], CONTOUR_NONE, key);
        if (k == CONTOUR_NONE || k == key) return s;
    }
    return CONTOUR_NONE;
}

// The node grid: a cell takes as many slots as its nodes need, all on its key's probe sequence before the first
// empty slot, so that a look-up finds every one and a crowded cell drops no node (which nodes it dropped depended
// on the order they came in). The slot of `key` at or after probe `probe` (then advanced past it), or NONE.
uint gridFind(uint key, inout uint probe) {
    const uint stride = CONTOUR_GRID_NODES + 1u;
    uint mask = pc.counts.z - 1u, h = contourHash(key);
    for (; probe < CONTOUR_PROBES; ++probe) {
        uint s = (h + probe) & mask, k = nodeGrid[stride * s];
        if (k == CONTOUR_NONE) return CONTOUR_NONE;
        if (k == key) {
            ++probe;
            return s;
        }
    }
    return CONTOUR_NONE;
}

#endif
