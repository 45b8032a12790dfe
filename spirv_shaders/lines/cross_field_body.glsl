// The body of cross_field.comp (and cross_field_large.comp): the hatching's cross field on the device, in float,
// one invocation a point, one dispatch a pass with a barrier between (shared/cross_field.h). Its CPU twin,
// solveCrossField (engine/lines/cross_field.cpp), does the same passes on the same graph in double; the equations
// are in cross_field.h:
//   seed: the shape operator S = P HF P / |∇F| in a tangent frame, its larger-|k| eigenvector ψ, confidence
//         c = a² / (1 + a²), a = |k1 − k2| · featureSize
//   sweep: z_i ← e^{4i·0} + Σ_j e^{4iθ_j} + fidelity · c_i · e^{4iψ_i},  θ_i ← arg(z_i) / 4
#include "shared/cross_field.h"
#include "refine/pu_hrbf.glsl"

layout(local_size_x = FIELD_GROUP_SIZE) in;

layout(std430, binding = FIELD_SAMPLES) readonly buffer Samples { vec4 samples[]; };
layout(std430, binding = FIELD_GRAPH) readonly buffer Graph { uint graph[]; };
layout(std430, binding = FIELD_STATE) buffer State { vec4 state[]; };
layout(std430, binding = FIELD_DIRECTIONS) buffer Directions { vec4 directions[]; };

layout(push_constant) uniform Params { FieldParams pc; };

uint points() { return pc.counts.x; }
uint neighbour(uint i, uint j) { return graph[i * pc.counts.y + j]; }
uint parentOf(uint i) { return graph[pc.counts.y * points() + i]; }
uint childStart(uint i) { return graph[(pc.counts.y + 1u) * points() + i]; }
uint child(uint c) { return graph[(pc.counts.y + 2u) * points() + 1u + c]; }

vec3 normalOf(uint i) { return state[i].xyz; }
float confidenceOf(uint i) { return state[i].w; }
vec3 seedOf(uint i) { return state[points() + i].xyz; }

// e^{4iθ} of u's direction in the frame (t1, t2) (fourthPower in cross_field.cpp); 0 for u ⟂ the plane.
vec2 fourthPower(vec3 u, vec3 t1, vec3 t2) {
    float x = dot(u, t1), y = dot(u, t2), r2 = x * x + y * y;
    if (!(r2 > 1e-30)) return vec2(0.0);
    float c = (x * x - y * y) / r2, s = 2.0 * x * y / r2;  // e^{2iθ}
    return vec2(c * c - s * s, 2.0 * c * s);
}

// arg(z) / 4 (GLSL's atan(0, 0) is undefined: 0 there, as C's atan2).
float quarterArg(vec2 z) { return z == vec2(0.0) ? 0.0 : 0.25 * atan(z.y, z.x); }

vec3 atAngle(vec3 t1, vec3 n, float theta) { return cos(theta) * t1 + sin(theta) * cross(n, t1); }

vec3 anyTangent(vec3 n) {
    vec3 a = abs(n.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(a - dot(a, n) * n);
}

// The start of a coarsest point whose curvature gives no direction (FIELD_START_CONFIDENCE).
vec3 axisTangent(vec3 n) {
    vec3 a = abs(n.y) < 0.95 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    return normalize(a - dot(a, n) * n);
}

void seed(uint i) {
    vec3 x = samples[2u * i].xyz, given = samples[2u * i + 1u].xyz;
    vec3 grad;
    mat3 H;
    puEvalHessian(x, grad, H);
    float g = length(grad);
    bool usable = g > 1e-12 && !any(isnan(grad)) && !any(isinf(grad));
    vec3 n = usable ? grad / g : normalize(given);
    if (dot(n, given) < 0.0) n = -n;
    vec3 t1 = anyTangent(n), t2 = cross(n, t1);
    float a = 0.0, b = 0.0, c = 0.0;
    bool finite = true;
    for (int k = 0; k < 3; ++k) finite = finite && !any(isnan(H[k])) && !any(isinf(H[k]));
    if (usable && finite) {
        a = dot(t1, H * t1) / g;
        b = dot(t1, H * t2) / g;
        c = dot(t2, H * t2) / g;
    }
    float spread = sqrt((a - c) * (a - c) + 4.0 * b * b);  // |k1 − k2|
    // The direction of the eigenvalue (a + c)/2 + spread/2; the other one has the larger |k| when a + c < 0.
    float psi = 0.5 * (vec2(2.0 * b, a - c) == vec2(0.0) ? 0.0 : atan(2.0 * b, a - c)) +
                (a + c < 0.0 ? 0.5 * 3.14159265358979 : 0.0);
    float s = spread * pc.options.y;
    bool sane = !isnan(s) && !isinf(s);
    state[i] = vec4(n, sane ? s * s / (1.0 + s * s) : 0.0);
    state[points() + i] = vec4(atAngle(t1, n, psi), 0.0);
}

void restrictSeed(uint r) {
    uint first = childStart(r), last = childStart(r + 1u), lead = child(first);
    vec3 n = normalOf(lead), t1 = seedOf(lead), t2 = cross(n, t1);
    vec2 sum = vec2(0.0);
    for (uint c = first; c < last; ++c) {
        uint k = child(c);
        sum += confidenceOf(k) * fourthPower(seedOf(k), t1, t2);
    }
    state[r] = vec4(n, length(sum) / float(last - first));
    state[points() + r] = vec4(atAngle(t1, n, quarterArg(sum)), 0.0);
}

void sweep(uint i) {
    uint from = pc.range.w * points(), to = (1u - pc.range.w) * points();
    vec3 n = normalOf(i), t1 = directions[from + i].xyz, t2 = cross(n, t1);
    vec2 z = vec2(1.0, 0.0);  // itself: a damped step
    for (uint j = 0u; j < pc.counts.y; ++j) {
        uint o = neighbour(i, j);
        if (o != FIELD_NONE) z += fourthPower(directions[from + o].xyz, t1, t2);
    }
    z += pc.options.x * confidenceOf(i) * fourthPower(seedOf(i), t1, t2);
    directions[to + i] = vec4(dot(z, z) > 1e-24 ? atAngle(t1, n, quarterArg(z)) : t1, 0.0);
}

// The parent's direction (in the half range.w) in this point's tangent plane, into the same half.
void prolong(uint i) {
    uint at = pc.range.w * points();
    vec3 up = directions[at + parentOf(i)].xyz, n = normalOf(i), t = up - dot(up, n) * n;
    directions[at + i] = vec4(length(t) > 1e-6 ? normalize(t) : seedOf(i), 0.0);
}

void main() {
    uint i = pc.range.x + gl_GlobalInvocationID.x;
    if (i >= pc.range.y) return;
    switch (pc.range.z) {
        case FIELD_PASS_SEED: seed(i); break;
        case FIELD_PASS_RESTRICT: restrictSeed(i); break;
        case FIELD_PASS_START:
            directions[pc.range.w * points() + i] =
                vec4(confidenceOf(i) >= FIELD_START_CONFIDENCE ? seedOf(i) : axisTangent(normalOf(i)), 0.0);
            break;
        case FIELD_PASS_SMOOTH: sweep(i); break;
        case FIELD_PASS_PROLONG: prolong(i); break;
    }
}
