// The body of contour_trace.comp (and contour_trace_large.comp): the occluding contour f = 0, g = 0
// (g = ∇f·(x − eye)) traced on the partition of unity, in float. The CPU tracer (engine/lines/lines.cpp,
// traceContours) follows the same curve one seed at a time; here every seed is projected at once and every node
// marches at once, to the next node along the curve.
// - CONTOUR_PASS_PROJECT: each seed that won its cell is corrected onto the contour by Newton steps (the
//   minimum-norm step of the 2×3 system, as contourNewton in lines.cpp) into a node, entered in the node grid.
// - CONTOUR_PASS_MARCH: each node marches along t = ∇f × ∇g (one orientation for the whole curve, so every march
//   runs the same way; in round 0 each seed also against it) by predictor–corrector steps, shorter where the curve
//   turns, until its chord crosses the normal plane of another node running along it within CONTOUR_MEET_STEPS
//   of it: the link the host follows to chain the curve (or back at itself, round a closed curve with one node).
#include "lines/contour_common.glsl"
#include "refine/pu_hrbf.glsl"

// One subgroup traces one node (a projection, a march): the steps are a chain, one after the other, and one
// invocation walking each evaluation's patches and nodes alone waits on every load in turn (on an H200 the bunny's
// contour took 20 ms so, 2.9 ms shared). The subgroup's invocations share each evaluation, one patch (and one
// far-field centre) each in turn, and add up; every invocation then holds the same sums and takes the same steps,
// so control flow stays uniform in the subgroup. (An invocation a march was faster on lavapipe, 85 against 440 ms,
// but what it drew there changed from run to run on the Wuson; `auto` traces on the CPU there anyway.)
uint lane() { return gl_SubgroupInvocationID; }
uint lanes() { return gl_SubgroupSize; }
bool leader() { return subgroupElect(); }
uint fromLeader(uint v) { return subgroupBroadcastFirst(v); }
float sum(float v) { return subgroupAdd(v); }
vec3 sum(vec3 v) { return subgroupAdd(v); }

// puEvalHessian (pu_hrbf.glsl) with its loops shared by the subgroup.
float puEvalHessianShared(vec3 x, out vec3 grad, out mat3 H) {
    PuHessianSums s = puNoSums();
    int cell = puCell(x);
    if (cell >= 0) {
        uint base = puCellCount() + 1u, k1 = puCells[cell + 1];
        for (uint k = puCells[cell] + lane(); k < k1; k += lanes()) puAddPatchHessian(puCells[base + k], x, s);
    }
    s.S = sum(s.S);
    s.N = sum(s.N);
    s.dS = sum(s.dS);
    s.dN = sum(s.dN);
    for (int c = 0; c < 3; ++c) {
        s.HS[c] = sum(s.HS[c]);
        s.HN[c] = sum(s.HN[c]);
    }
    float fc = 0.0;
    vec3 gc = vec3(0.0);
    mat3 Hc = mat3(0.0);
    if (s.S < pu.params.x) {
        for (uint j = lane(); j < pu.dims.w; j += lanes())
            hrbfNodeHessianF(x, puCoarse[2u * j], puCoarse[2u * j + 1u].xyz, fc, gc, Hc);
        fc = sum(fc) + dot(pu.coarseLinear.xyz, x) + pu.coarseLinear.w;
        gc = sum(gc) + pu.coarseLinear.xyz;
        for (int c = 0; c < 3; ++c) Hc[c] = sum(Hc[c]);
    }
    return puFinishHessian(x, s, fc, gc, Hc, grad, H);
}

// Newton onto (f, g) = 0 from x, moving at most maxMove: the minimum-norm step of the 2×3 system
// J = [∇f; ∇g], ∇g = H (x − eye) + ∇f, as contourNewton in lines.cpp. On success x is on the contour and n, t are
// the unit normal and the unit tangent ∇f × ∇g there (of the last evaluation, within 1e-6 of x). The Hessian is
// evaluated at every iteration: with it held from the first (a simplified Newton) the tangents were noisier, the
// steps shorter and the bunny's contour had 68 cusps instead of 58.
bool contourNewton(inout vec3 x, float maxMove, uint iterations, out vec3 n, out vec3 t) {
    const vec3 start = x;
    n = t = vec3(0.0);
    for (uint i = 0u; i < iterations; ++i) {
        vec3 gF;
        mat3 H;
        float f = puEvalHessianShared(x, gF, H);
        if (leader()) atomicAdd(counters.evaluations, 1u);
        vec3 r = x - pc.eye.xyz, gG = H * r + gF;
        float g = dot(gF, r);
        float a = dot(gF, gF), b = dot(gF, gG), c = dot(gG, gG);
        precise float det = a * c - b * b;
        if (!(det > 1e-6 * a * c)) return false;  // ∇f ∥ ∇g: a singular point of the contour
        float y0 = (c * f - b * g) / det, y1 = (a * g - b * f) / det;
        vec3 dx = -(y0 * gF + y1 * gG);
        x += dx;
        if (any(isnan(x)) || any(isinf(x)) || length(x - start) > maxMove) return false;
        float moved = length(dx);
        if (moved < 1e-6 || (i + 1u == iterations && moved < 1e-5)) {
            n = normalize(gF);
            vec3 c3 = cross(gF, gG);
            if (!(length(c3) > 1e-6 * sqrt(a * c))) return false;
            t = normalize(c3);
            return true;
        }
    }
    return false;
}

uint addNode(vec3 x, vec3 n, vec3 t, uint round, bool backward);

void project(uint listed) {
    if (listed >= counters.listed) return;
    vec3 x = seedList[listed].xyz, n, t;
    if (contourNewton(x, pc.sizes.y, 5u, n, t) && leader()) addNode(x, n, t, 0u, false);
}

bool lessThanVec(vec3 a, vec3 b) { return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z))); }

// The first node whose normal plane (through it, across its tangent) the chord x → y crosses, within `reach` of
// it, its tangent along the chord's either way (t·t_j: the orientation ∇f × ∇g flips where ∇f × H (x − eye)
// passes near 0, and the float Hessian's noise decides where; the ports put it together): its index, or NONE;
// `along` is whether it runs the same way as t. Crossing the plane, not passing within a hair of the point: where
// g's gradient is small, float leaves the contour's position uncertain across the curve, and two projections of
// one place differ by a pixel. A node counts when x lies strictly before its plane, so that two nodes at one
// place do not meet each other and close a curve of nothing; node `self` counts only once the march has gone
// `away` along the curve (round a closed curve).
uint nodeOnChord(vec3 x, vec3 y, vec3 t, float reach, uint self, bool away, out bool along) {
    // The subgroup shares the 27 cells, a cell an invocation in turn (one step's search was 27 hash probes in a row
    // for each invocation alike), each keeping its best in the order below; then the best of those, the earliest
    // cell among equals: the node one invocation searching every cell in turn would find.
    float bestU = 2.0, bestDistance = 0.0;
    vec3 bestP = vec3(0.0);
    uint found = CONTOUR_NONE, bestCell = 27u;
    bool bestAlong = true;
    ivec3 c = contourCell(y);
    for (uint cell = lane(); cell < 27u; cell += lanes()) {
        ivec3 d = ivec3(int(cell % 3u), int((cell / 3u) % 3u), int(cell / 9u)) - 1;
        uint key = contourCellKey(c + d), probe = 0u;
        for (uint s = gridFind(key, probe); s != CONTOUR_NONE; s = gridFind(key, probe))
            for (uint e = 1u; e <= CONTOUR_GRID_NODES; ++e) {
                uint j = nodeGrid[(CONTOUR_GRID_NODES + 1u) * s + e];
                if (j == CONTOUR_NONE) break;
                if (j == self && !away) continue;
                vec3 p = nodes[j].position.xyz, tj = nodes[j].tangent.xyz;
                float c = dot(tj, t);
                if (abs(c) < 0.7) continue;
                vec3 tt = c > 0.0 ? tj : -tj;
                float sx = dot(x - p, tt), sy = dot(y - p, tt);
                if (!(sx < 0.0 && sy >= 0.0)) continue;
                float u = sx / (sx - sy), distance = length(x + u * (y - x) - p);
                if (distance > reach) continue;
                // The first along the chord; among equals the nearest, then the least position: not the order
                // the nodes entered the grid in.
                if (u > bestU || (u == bestU && (distance > bestDistance ||
                                                 (distance == bestDistance && !lessThanVec(p, bestP)))))
                    continue;
                bestU = u;
                bestDistance = distance;
                bestP = p;
                found = j;
                bestCell = cell;
                bestAlong = c > 0.0;
            }
    }
    const float none = 3.0e38;
    bool best = found != CONTOUR_NONE;
    float least = subgroupMin(best ? bestU : none);
    best = best && bestU == least;
    least = subgroupMin(best ? bestDistance : none);
    best = best && bestDistance == least;
    for (int k = 0; k < 3; ++k) {
        least = subgroupMin(best ? bestP[k] : none);
        best = best && bestP[k] == least;
    }
    best = best && bestCell == subgroupMin(best ? bestCell : 27u);
    along = subgroupMin(best && !bestAlong ? 0u : 1u) == 1u;
    return subgroupMin(best ? found : CONTOUR_NONE);
}

// Enters node k in the node grid: in its cell's first slot with room, claiming another when they are full.
bool enterNode(uint k, vec3 x) {
    const uint stride = CONTOUR_GRID_NODES + 1u;
    uint key = contourCellKey(contourCell(x)), mask = pc.counts.z - 1u, h = contourHash(key);
    for (uint probe = 0u; probe < CONTOUR_PROBES; ++probe) {
        uint s = (h + probe) & mask, owner = nodeGrid[stride * s];
        if (owner == CONTOUR_NONE) {
            owner = atomicCompSwap(nodeGrid[stride * s], CONTOUR_NONE, key);
            if (owner == CONTOUR_NONE) owner = key;
        }
        if (owner != key) continue;
        for (uint e = 1u; e <= CONTOUR_GRID_NODES; ++e)
            if (atomicCompSwap(nodeGrid[stride * s + e], CONTOUR_NONE, k) == CONTOUR_NONE) return true;
    }
    atomicAdd(counters.lost, 1u);
    return false;
}

// A new node at x, whose forward march runs in round `round` (against the curve's orientation when `backward`,
// ContourNode::state.y): its index, or NONE when the array is full. It enters the node grid in the next
// CONTOUR_PASS_ENTER, before the next marches, so that what a march meets does not depend on which other marches
// of its pass ran first. The march passes take two subgroups a node (its forward march, and in round 0 its
// backward one).
uint addNode(vec3 x, vec3 n, vec3 t, uint round, bool backward) {
    uint k = atomicAdd(counters.nodes, 1u);
    if (k >= pc.limits.x) return CONTOUR_NONE;
    nodes[k].position = vec4(x, 0.0);
    nodes[k].normal = vec4(n, 0.0);
    nodes[k].tangent = vec4(t, 0.0);
    nodes[k].state = uvec4(round, backward ? 1u : 0u, 0u, 0u);
    nodes[k].forward = nodes[k].backward = uvec4(CONTOUR_NONE, 0u, 0u, 0u);
    atomicMax(counters.march.x, (2u * k + 1u) / pc.shape.x + 1u);
    return k;
}

// One march from node k, along its tangent (forward) or against it, until it meets a node: the link
// (met node, first vertex, vertex count, CONTOUR_* bits). A march that takes CONTOUR_MARCH_VERTICES without
// meeting one (the seeds missed a stretch of the curve) leaves a new node where it stopped, which marches on
// forward in the next round; in the last round it ends there.
uvec4 march(uint k, bool forward, uint round) {
    ContourNode start = nodes[k];
    const float step = pc.eye.w;
    // Room for the most vertices a march makes, taken first; vertex v is written by invocation v mod lanes() as
    // it comes. (Held in private arrays instead, 48 of them, lavapipe lost some when an invocation marched alone:
    // the Wuson had 168 marches with stale vertices, straight lines across the drawing.)
    uint first = 0u;
    if (leader()) first = atomicAdd(counters.vertices, CONTOUR_MARCH_VERTICES);
    first = fromLeader(first);
    if (first + CONTOUR_MARCH_VERTICES > pc.limits.y) return uvec4(CONTOUR_NONE, 0u, 0u, CONTOUR_OVERFLOW);
    vec3 x = start.position.xyz, t = forward ? start.tangent.xyz : -start.tangent.xyz, lastNormal = start.normal.xyz;
    if (lane() == 0u) {
        vertices[first].position = vec4(x, 0.0);
        vertices[first].normal = start.normal;
    }
    uint m = 1u, next = CONTOUR_NONE, how = CONTOUR_TOO_LONG;
    float h = step, arc = 0.0;
    // Each pass makes one predictor step and its corrector: at most CONTOUR_MARCH_VERTICES accepted, and every
    // rejected one halves h (down to step / 16, then the march is stuck), so the loop is bounded.
    for (uint pass = 0u; pass < 4u * CONTOUR_MARCH_VERTICES; ++pass) {
        if (m == CONTOUR_MARCH_VERTICES) break;
        vec3 y = x + h * t, n, ty;
        if (!contourNewton(y, 2.0 * max(h, step), 10u, n, ty) || distance(x, y) < CONTOUR_LEAST_PROGRESS * h) {
            if (h <= step / 16.0) {
                how = CONTOUR_STUCK;
                break;
            }
            h *= 0.5;
            continue;
        }
        if (dot(ty, t) < 0.0) ty = -ty;
        bool along;
        uint j = nodeOnChord(x, y, t, CONTOUR_MEET_STEPS * step, k, arc > 3.0 * step, along);
        if (j != CONTOUR_NONE) {
            // Running along j's tangent it arrives at j's back; against it, at j's front.
            next = j;
            how = CONTOUR_MET | (along ? 0u : CONTOUR_AT_FORWARD);
            break;
        }
        arc += distance(x, y);
        // Shorter steps where the curve turns (the chord stays within a fraction of a pixel), longer where it runs
        // straight: as the CPU tracer.
        float turn = acos(clamp(dot(ty, t), -1.0, 1.0));
        if (turn > 0.15)
            h = max(step / 16.0, h * 0.5);
        else if (turn < 0.05)
            h = min(CONTOUR_LONGEST_STEP * step, h * 1.5);
        if (m % lanes() == lane()) {
            vertices[first + m].position = vec4(y, 0.0);
            vertices[first + m].normal = vec4(n, 0.0);
        }
        lastNormal = n;
        ++m;
        x = y;
        t = ty;
    }
    if (how == CONTOUR_TOO_LONG && round + 1u < pc.limits.w) {
        // Go on from the last vertex in the next round: it becomes that node's first, arrived at from behind.
        uint j = CONTOUR_NONE;
        if (leader()) j = addNode(x, lastNormal, t, round + 1u, !forward || start.state.y != 0u);
        j = fromLeader(j);
        if (j != CONTOUR_NONE) {
            --m;
            next = j;
            how = CONTOUR_MET;
        }
    }
    return uvec4(next, first, m, how);
}

void main() {
    // One subgroup a seed or a march; one invocation a node for the grid.
    const uint item = gl_WorkGroupID.x * gl_NumSubgroups + gl_SubgroupID;
    if (pc.counts.w == CONTOUR_PASS_PROJECT) {
        project(item);
        return;
    }
    if (pc.counts.w == CONTOUR_PASS_ENTER) {
        // No node is made in this pass: its count is the next marches' (which make nodes as they go, and must not
        // march one a march of their own pass is still writing).
        uint i = gl_GlobalInvocationID.x, count = min(counters.nodes, pc.limits.x);
        if (i == 0u) counters.marching = count;
        if (i < count && nodes[i].state.z == 0u) {
            enterNode(i, nodes[i].position.xyz);
            nodes[i].state.z = 1u;
        }
        return;
    }
    // Two subgroups a node: its forward march in its round, and a seed's backward one in round 0 (every seed
    // marches both ways at once; where two marches trace one stretch from either end, chainMarches keeps the
    // shorter: twice the work of marching backward only from the seeds no forward march arrived at, but in one
    // pass, not two after each other).
    const uint k = item >> 1u, round = pc.limits.z;
    const bool forward = (item & 1u) == 0u;
    if (k >= counters.marching || nodes[k].state.x != round || !(forward || round == 0u)) return;
    uvec4 link = march(k, forward, round);
    if (leader()) {
        if (forward)
            nodes[k].forward = link;
        else
            nodes[k].backward = link;
    }
}
