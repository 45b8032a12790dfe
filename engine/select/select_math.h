// The stipple selection's per-point arithmetic, twin of spirv_shaders/select/select_common.glsl: cells, phases,
// priorities, pools, distances and orders, written operation for operation as the shaders so that both
// backends decide the same (no fused multiply-adds on either side: see select_cpu.cpp).
#pragma once

#include "base/random.h"
#include "select/select_plan.h"

#include <cmath>

namespace ink {

struct CellKey {
    int x, y, z;
    bool operator==(const CellKey&) const = default;
};

inline CellKey cellOfPoint(const float p[3], const SelectStage& s) {
    float x = (p[0] + s.offset[0]) * s.cellScale;
    float y = (p[1] + s.offset[1]) * s.cellScale;
    float z = (p[2] + s.offset[2]) * s.cellScale;
    return {int(std::floor(x)), int(std::floor(y)), int(std::floor(z))};
}

// Cells whose coordinates have the same parities form a phase: two of them are at least a cell side apart.
inline uint32_t cellPhase(const CellKey& c) {
    return (uint32_t(c.x) & 1u) | ((uint32_t(c.y) & 1u) << 1) | ((uint32_t(c.z) & 1u) << 2);
}

// For the reference's hash map only (the device orders its buckets by Morton code: select_common.glsl).
inline uint32_t cellHash(const CellKey& c) {
    uint32_t h = (uint32_t(c.x) * 73856093u) ^ (uint32_t(c.y) * 19349663u) ^ (uint32_t(c.z) * 83492791u);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    return h;
}

inline uint32_t stagePriority(const SelectStage& s, uint32_t point) { return pcg4d({s.seed, point, 0u, 0u})[0]; }

// Whether a candidate is in the pool of a stage: its pool key under the stage's threshold. Keys are fixed per
// candidate, so the pools are nested, and a finer stage's pool holds every point the coarser ones selected.
inline uint32_t poolKey(uint32_t seed, uint32_t point) { return pcg4d({seed, point, 0x9001u, 0u})[0]; }
inline bool inPool(uint32_t key, const SelectStage& s) {
    return s.poolThreshold == 0xFFFFFFFFu || key < s.poolThreshold;
}

// Higher priority first; equal priorities by candidate index.
inline bool priorityBefore(uint32_t pa, uint32_t a, uint32_t pb, uint32_t b) { return pa > pb || (pa == pb && a < b); }

// The squared distance of two points on the same side of the surface; points whose normals are more than 120°
// apart (the two sides of a thin part) never suppress each other.
inline float sameSideDistance2(const PointRecord& a, const PointRecord& b) {
    float facing = a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] + a.normal[2] * b.normal[2];
    if (!(facing > -0.5f)) return INFINITY;
    float dx = a.position[0] - b.position[0], dy = a.position[1] - b.position[1], dz = a.position[2] - b.position[2];
    return dx * dx + dy * dy + dz * dz;
}

// u(p) of a point stage s > 0 added, from its squared distance d² to the nearest point of the earlier stages
// (found within the 27 cells around it): 0 at R_{s−1} or beyond (the largest holes), towards 1 at R_s.
inline float additionOrder(const SelectStage& s, float d2) {
    float u = (s.previousRadius2 - d2) * s.orderScale;
    return u > 0.0f ? (u < 0.99999994f ? u : 0.99999994f) : 0.0f;
}

// The first stage's points are ordered by a random u.
inline float firstStageOrder(const SelectStage& s, uint32_t point) {
    return unitFloats(pcg4d({s.seed, point, 0xFACEu, 0u}))[0];
}

}  // namespace ink
