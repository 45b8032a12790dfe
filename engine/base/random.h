// The counter-based hash shared with spirv_shaders/common.glsl: the same (seed, level, parent, child)
// gives the same numbers on the CPU and on any GPU, whatever the thread schedule.
#pragma once

#include <array>
#include <cstdint>

namespace ink {

// PCG-based 4D hash (Jarzynski & Olano 2020), bit-identical to pcg4d() in common.glsl.
inline std::array<uint32_t, 4> pcg4d(std::array<uint32_t, 4> v) {
    for (uint32_t& x : v) x = x * 1664525u + 1013904223u;
    v[0] += v[1] * v[3];
    v[1] += v[2] * v[0];
    v[2] += v[0] * v[1];
    v[3] += v[1] * v[2];
    for (uint32_t& x : v) x ^= x >> 16u;
    v[0] += v[1] * v[3];
    v[1] += v[2] * v[0];
    v[2] += v[0] * v[1];
    v[3] += v[1] * v[2];
    return v;
}

// Uniform in [0,1) from the top 24 bits, as unitFloats() in common.glsl.
inline std::array<float, 4> unitFloats(std::array<uint32_t, 4> u) {
    return {float(u[0] >> 8) * (1.0f / 16777216.0f), float(u[1] >> 8) * (1.0f / 16777216.0f),
            float(u[2] >> 8) * (1.0f / 16777216.0f), float(u[3] >> 8) * (1.0f / 16777216.0f)};
}

}  // namespace ink
