#version 460
#extension GL_GOOGLE_include_directive : require
// One refinement level (report §4.2): each invocation makes one child of a parent point on its tangent
// plane (stippling or direction sampling), or takes one seed, and projects it onto f = 0 (eq. 11).
#include "refine_bindings.glsl"
#include "hrbf.glsl"

layout(local_size_x = 256) in;

shared uint groupKept;

const uint KEPT = 4u;

// Eq. 11 with the Armijo rule: p ← p − δ^i f/‖∇f‖² ∇f, i the smallest with f(p′)² ≤ f(p)²(1 − 2φδ^i).
uint project(inout dvec3 p, out dvec3 grad) {
    dvec3 g;
    double f = hrbfEval(p, g);
    for (uint it = 0u;; ++it) {
        double gg = dot(g, g);
        if (gg < double(pc.eps2) * double(pc.eps2)) return DROP_GRADIENT;
        if (abs(f) < double(pc.eps1) * sqrt(gg)) {
            grad = g;
            return KEPT;
        }
        if (it == pc.maxIterations) return DROP_ITERATIONS;
        dvec3 step = (f / gg) * g;
        double t = 1.0LF;  // δ^i
        for (uint i = 0u;; ++i) {
            dvec3 gq;
            dvec3 q = p - t * step;
            double fq = hrbfEval(q, gq);
            if (fq * fq <= f * f * (1.0LF - 2.0LF * double(pc.phi) * t)) {
                p = q;
                f = fq;
                g = gq;
                break;
            }
            if (i == 16u) return DROP_ARMIJO;  // i_k > 16
            t *= double(pc.delta);
        }
    }
}

// A unit vector perpendicular to n without branches on the sign (Stark 2009 style).
vec3 perpendicular(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    return vec3(1.0 + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x);
}

// The report's random frame: r′ = R n for a random rotation R (axis, angle); u = n × r′, r = n × u.
void randomFrame(vec3 n, uint parent, out vec3 r, out vec3 u) {
    vec4 q = unitFloats(pcg4d(uvec4(pc.seed, pc.level, parent, 0xFFFFFFFFu)));
    float z = 1.0 - 2.0 * q.x, phi = 6.28318530718 * q.y, theta = 6.28318530718 * q.z;
    vec3 axis = vec3(sqrt(max(0.0, 1.0 - z * z)) * vec2(cos(phi), sin(phi)), z);
    // Rodrigues' rotation of n about axis by theta.
    vec3 rp = n * cos(theta) + cross(axis, n) * sin(theta) + axis * dot(axis, n) * (1.0 - cos(theta));
    vec3 c = cross(n, rp);
    u = dot(c, c) > 1e-12 ? normalize(c) : perpendicular(n);
    r = cross(n, u);
}

// A smooth tangent field for direction sampling: the projected axis, or a principal direction.
vec3 tangentDirection(vec3 position, vec3 n, vec3 fallback) {
    if (pc.direction == 0u) {
        vec3 d = pc.axis.xyz - dot(pc.axis.xyz, n) * n;
        return dot(d, d) > 1e-8 ? normalize(d) : fallback;
    }
    dvec3 gd;
    dmat3 Hd;
    hrbfEvalHessian(dvec3(position), gd, Hd);
    mat3 H = mat3(Hd);
    float gn = float(length(gd));
    vec3 t1 = perpendicular(n), t2 = cross(n, t1);
    // Shape operator on the tangent plane (2×2, symmetric) and its eigenvectors.
    float a = dot(t1, H * t1) / gn, b = dot(t1, H * t2) / gn, c = dot(t2, H * t2) / gn;
    float mean = 0.5 * (a + c), radius = sqrt(0.25 * (a - c) * (a - c) + b * b);
    if (radius < 1e-6 * (abs(mean) + 1e-6)) return fallback;  // umbilic: no preferred direction
    float k = pc.direction == 1u ? mean - radius : mean + radius;
    // (b, k − a) is an eigenvector of [[a b][b c]] for eigenvalue k unless it vanishes; then (k − c, b).
    vec2 e = abs(k - a) + abs(b) > abs(k - c) + abs(b) ? vec2(b, k - a) : vec2(k - c, b);
    return normalize(e.x * t1 + e.y * t2);
}

void main() {
    if (gl_LocalInvocationIndex == 0u) groupKept = 0u;
    barrier();

    uint i = gl_GlobalInvocationID.x;
    uint L = pc.level;
    uint count = levels[L].candidates;
    if (i < count) {
        uint parentIndex = i / pc.childCount, child = i % pc.childCount;
        vec4 rnd = unitFloats(pcg4d(uvec4(pc.seed, L, parentIndex, child)));
        vec3 origin, start;
        if (pc.mode == 0u) {
            origin = seeds[i].xyz;
            start = origin;
        } else {
            Point parent = points[levels[L].parentOffset + parentIndex];
            origin = parent.position;
            vec3 r, u;
            randomFrame(parent.normal, parentIndex, r, u);
            if (pc.mode == 1u) {
                // Stippling: p + iρ r + jρ u with i, j ∈ {±1 + m}, m ∈ [−⅛, ⅛] fresh for each.
                float si = (child & 1u) != 0u ? 1.0 : -1.0, sj = (child & 2u) != 0u ? 1.0 : -1.0;
                float mi = 0.25 * rnd.x - 0.125, mj = 0.25 * rnd.y - 0.125;
                start = origin + (si + mi) * pc.rho * r + (sj + mj) * pc.rho * u;
            } else {
                // Direction sampling: p ± ρ d along a smooth tangent field.
                vec3 d = tangentDirection(origin, parent.normal, r);
                start = origin + (child == 0u ? -pc.rho : pc.rho) * d;
            }
        }
        dvec3 p = dvec3(start), g = dvec3(0.0LF);
        uint result = project(p, g);
        if (result == KEPT && distance(vec3(p), origin) > pc.jumpLimit) result = DROP_JUMP;
        bool kept = result == KEPT;
        if (kept) {
            candidates[i] = Point(vec3(p), L, vec3(normalize(g)), pc.toneOffset + pc.toneScale * rnd.z);
            atomicAdd(groupKept, 1u);
        } else {
            atomicAdd(levels[L].dropped[result], 1u);
        }
        flags[i] = kept ? 1u : 0u;
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) blockSums[gl_WorkGroupID.x] = groupKept;
}
