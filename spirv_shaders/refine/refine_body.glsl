// The body of refine.comp and refine_global.comp (one refinement level); see refine.comp.
// One refinement level (report §4.2): each invocation makes one child of a parent point on its tangent
// plane (stippling or direction sampling), or takes one seed, and projects it onto f = 0 (eq. 11).
#include "refine/refine_bindings.glsl"

// The surface: the partition of unity in float (the default), or the report's global HRBF in double
// (refine_global.comp, for --fit global on devices with shaderFloat64).
#ifdef HRBF_GLOBAL
#include "refine/hrbf.glsl"
#define REAL double
#define RVEC3 dvec3
REAL surfaceEval(RVEC3 x, out RVEC3 g) { return hrbfEval(x, g); }
float surfaceEvalHessian(vec3 x, out vec3 g, out mat3 H) {
    dvec3 gd;
    dmat3 Hd;
    double f = hrbfEvalHessian(dvec3(x), gd, Hd);
    g = vec3(gd);
    H = mat3(Hd);
    return float(f);
}
#else
#include "refine/pu_hrbf.glsl"
#define REAL float
#define RVEC3 vec3
REAL surfaceEval(RVEC3 x, out RVEC3 g) { return puEval(x, g); }
float surfaceEvalHessian(vec3 x, out vec3 g, out mat3 H) { return puEvalHessian(x, g, H); }
#endif

layout(local_size_x = GROUP_SIZE) in;

shared uint groupKept;

const uint KEPT = 4u;

// Eq. 11 with the Armijo rule: p ← p − δ^i f/‖∇f‖² ∇f, i the smallest with f(p′)² ≤ f(p)²(1 − 2φδ^i).
// surfaceEval may need the whole subgroup active, so the projection is a state machine in one subgroup-uniform
// loop: each pass makes one evaluation for every invocation, at its next point (or again at its last one once
// it is done or out of range), until all are done. Per invocation it makes the same evaluations and decisions,
// in the same order, as the nested loops of engine/refine/refine_cpu.cpp's Projector.
const uint START = 0u;  // evaluating the starting point
const uint TRIAL = 1u;  // evaluating an Armijo trial point q = p − δ^i step
const uint DONE = 2u;

uint project(bool inRange, inout RVEC3 p, out RVEC3 grad) {
    uint state = inRange ? START : DONE, result = DROP_ITERATIONS;
    uint it = 0u, i = 0u;  // iteration, Armijo exponent
    REAL f = REAL(0.0), t = REAL(1.0);  // f(p), δ^i
    RVEC3 g = RVEC3(0.0), step = g, q = p;  // ∇f(p), the Newton step, the point being evaluated
    grad = RVEC3(0.0);
    while (subgroupAny(state != DONE)) {
        RVEC3 gq;
        REAL fq = surfaceEval(q, gq);
        if (state == START) {
            f = fq;
            g = gq;
        } else if (state == TRIAL) {
            if (fq * fq <= f * f * (REAL(1.0) - REAL(2.0) * REAL(pc.phi) * t)) {
                p = q;
                f = fq;
                g = gq;
                ++it;
            } else if (i == 16u) {  // i_k > 16
                result = DROP_ARMIJO;
                state = DONE;
            } else {
                t *= REAL(pc.delta);
                ++i;
                q = p - t * step;
                continue;
            }
        }
        if (state == DONE) continue;
        // At p with f, g: stop, or start the Armijo trials of iteration `it`.
        REAL gg = dot(g, g);
        if (gg < REAL(pc.eps2) * REAL(pc.eps2)) {
            result = DROP_GRADIENT;
            state = DONE;
        } else if (abs(f) < REAL(pc.eps1) * sqrt(gg)) {
            grad = g;
            result = KEPT;
            state = DONE;
        } else if (it == pc.maxIterations) {
            result = DROP_ITERATIONS;
            state = DONE;
        } else {
            step = (f / gg) * g;
            t = REAL(1.0);
            i = 0u;
            q = p - t * step;
            state = TRIAL;
        }
    }
    return result;
}

// A unit vector perpendicular to n without branches on the sign (Stark 2009 style).
vec3 perpendicular(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    return vec3(1.0 + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x);
}

// The report's random frame: r′ = R n for a random rotation R (axis, angle); u = n × r′, r = n × u.
// Each pass of children (level 1) turns its own frame.
void randomFrame(vec3 n, uint parent, uint pass, out vec3 r, out vec3 u) {
    vec4 q = unitFloats(pcg4d(uvec4(pc.seed, pc.level, parent, 0xFFFFFFFFu - pass)));
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
    vec3 gd;
    mat3 H;
    surfaceEvalHessian(position, gd, H);
    float gn = length(gd);
    vec3 t1 = perpendicular(n), t2 = cross(n, t1);
    // Shape operator on the tangent plane (2×2, symmetric) and its eigenvectors.
    // precise: no fused multiply-adds here, so that every device rounds these as the CPU reference does.
    precise float a = dot(t1, H * t1) / gn, b = dot(t1, H * t2) / gn, c = dot(t2, H * t2) / gn;
    precise float mean = 0.5 * (a + c), radius = sqrt(0.25 * (a - c) * (a - c) + b * b);
    if (radius < 1e-6 * (abs(mean) + 1e-6)) return fallback;  // umbilic: no preferred direction
    float k = pc.direction == 1u ? mean - radius : mean + radius;
    // (b, k − a) is an eigenvector of [[a b][b c]] for eigenvalue k unless it vanishes; then (k − c, b).
    vec2 e = abs(k - a) + abs(b) > abs(k - c) + abs(b) ? vec2(b, k - a) : vec2(k - c, b);
    // The two forms differ in sign by b / (k − a): a device whose rounding picks the other form near a ≈ c would
    // swap the ± children. One sign for the line field: along +t1 (+t2 when across it).
    if (e.x < 0.0 || (e.x == 0.0 && e.y < 0.0)) e = -e;
    return normalize(e.x * t1 + e.y * t2);
}

void main() {
    if (gl_LocalInvocationIndex == 0u) groupKept = 0u;
    barrier();

    uint i = gl_GlobalInvocationID.x;
    uint L = pc.level;
    uint count = levels[L].candidates;
    bool inRange = i < count;
    vec3 origin = vec3(0.0), start = vec3(0.0);
    vec4 rnd = vec4(0.0);
    if (inRange) {
        uint parentIndex = i / pc.childCount, child = i % pc.childCount;
        uint pass = child / pc.passChildren, sub = child % pc.passChildren;
        rnd = unitFloats(pcg4d(uvec4(pc.seed, L, parentIndex, child)));
        if (pc.mode == 0u) {
            origin = seeds[i].xyz;
            start = origin;
        } else {
            Point parent = points[levels[L].parentOffset + parentIndex];
            origin = parent.position;
            vec3 r, u;
            randomFrame(parent.normal, parentIndex, pass, r, u);
            if (pc.mode == 1u) {
                // Stippling: p + iρ r + jρ u with i, j ∈ {±1 + m}, m ∈ [−⅛, ⅛] fresh for each.
                float si = (sub & 1u) != 0u ? 1.0 : -1.0, sj = (sub & 2u) != 0u ? 1.0 : -1.0;
                float mi = 0.25 * rnd.x - 0.125, mj = 0.25 * rnd.y - 0.125;
                start = origin + (si + mi) * pc.rho * r + (sj + mj) * pc.rho * u;
            } else {
                // Direction sampling: p ± ρ d along a smooth tangent field; a further pass starts a line
                // beside it, shifted across the field by up to ρ.
                vec3 d = tangentDirection(origin, parent.normal, r);
                start = origin + (sub == 0u ? -pc.rho : pc.rho) * d;
                if (pass > 0u) start += (2.0 * rnd.y - 1.0) * pc.rho * cross(parent.normal, d);
            }
        }
    }
    // Out of the branch: the projection runs in subgroup-uniform control flow (see project()).
    RVEC3 p = RVEC3(start), g;
    uint result = project(inRange, p, g);
    if (inRange) {
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
