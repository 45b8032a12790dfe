// Point records, the counter-based random numbers, and the refinement's device-side bookkeeping.
// The layouts are spirv_shaders/shared/refine.h's; the C++ twin of pcg4d is engine/base/random.h.
#ifndef COMMON_GLSL
#define COMMON_GLSL

#include "shared/refine.h"  // Point, LevelInfo, MAX_LEVELS, DROP_*

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

// An orthonormal tangent frame of the unit normal n, continuous except where n.z changes sign (Duff et al. 2017,
// "Building an orthonormal basis, revisited"): shape.comp stores a point's shape operator in it, splat.comp reads
// it back in the same frame.
void tangentFrame(vec3 n, out vec3 t1, out vec3 t2) {
    float s = n.z >= 0.0 ? 1.0 : -1.0, a = -1.0 / (s + n.z), b = n.x * n.y * a;
    t1 = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    t2 = vec3(b, s + n.y * n.y * a, -n.y);
}

#endif
