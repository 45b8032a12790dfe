// Point records, the counter-based random numbers, and the refinement's device-side bookkeeping.
// The C++ twins are engine/refine.h (layouts) and engine/random.h (pcg4d).
#ifndef COMMON_GLSL
#define COMMON_GLSL

// 32 bytes a point, in normalized model coordinates.
struct Point {
    vec3 position;
    uint level;
    vec3 normal;  // unit ∇f
    float tone;   // fixed random value in [0,1): decides whether tone draws the point
};

const uint MAX_LEVELS = 16u;
const uint DROP_GRADIENT = 0u;    // ‖∇f‖ < ε₂
const uint DROP_ARMIJO = 1u;      // i_k > 16
const uint DROP_ITERATIONS = 2u;  // iteration cap reached
const uint DROP_JUMP = 3u;        // moved too far from its parent (another sheet)

struct LevelInfo {
    uint candidates;    // candidates generated at this level
    uint parentOffset;  // first parent in the point buffer
    uint keptOffset;    // first kept point in the point buffer
    uint kept;
    uint dropped[4];
};

// PCG-based 4D hash (Jarzynski & Olano 2020): (seed, level, parent, child) -> 4 independent uints.
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// Uniform in [0,1) from the top 24 bits, exactly representable in float.
vec4 unitFloats(uvec4 u) { return vec4(u >> 8u) * (1.0 / 16777216.0); }

#endif
