// The occluding contour traced on the device (contour_seeds.comp, contour_trace.comp; engine/lines/contour_device.cpp):
// the push constants, the nodes and vertices it writes, and its descriptor set's bindings (see interface.h). The
// set also holds the refinement's surface bindings (shared/refine.h: REFINE_SURFACE_HEADER, REFINE_PU_*), which
// pu_hrbf.glsl reads.
#ifndef INK_SHARED_CONTOUR_H
#define INK_SHARED_CONTOUR_H

#include "interface.h"

INK_BEGIN

// A march from one node stops after this many vertices (the node's own included) without meeting another node, and
// goes on from a new node in the next round, up to CONTOUR_ROUNDS. It takes room for this many in the vertex array
// when it starts.
INK_CONST uint CONTOUR_MARCH_VERTICES = 48u;
INK_CONST uint CONTOUR_GROUP_SIZE = 64u;
// The longest predictor step, in steps (ContourOptions::step), where the curve runs straight.
INK_CONST float CONTOUR_LONGEST_STEP = 4.0;
// A corrected step that lands less than this fraction of the predictor step h from where it began made no
// progress (the corrector pulls it back towards a singular point, where the steps shrink geometrically): it counts
// as rejected. The CPU tracer (lines.cpp) uses the same.
INK_CONST float CONTOUR_LEAST_PROGRESS = 0.25;
// A march meets a node when it crosses the node's normal plane within this many steps of it.
INK_CONST float CONTOUR_MEET_STEPS = 2.0;
// A node-grid slot: its cell key, then up to this many nodes.
INK_CONST uint CONTOUR_GRID_NODES = 15u;
INK_CONST uint CONTOUR_NONE = 0xFFFFFFFFu;
INK_CONST uint CONTOUR_SEED_SLOT = 5u;
// A march's bits (ContourNode::forward.w, backward.w): how it ended.
INK_CONST uint CONTOUR_MET = 1u;       // at a node (x), possibly itself round a closed curve
INK_CONST uint CONTOUR_STUCK = 2u;     // the corrector failed at the smallest step (a singular point, the grid's end)
INK_CONST uint CONTOUR_TOO_LONG = 4u;  // CONTOUR_MARCH_VERTICES without meeting a node
INK_CONST uint CONTOUR_OVERFLOW = 8u;  // the vertex array was full: the march did not start
INK_CONST uint CONTOUR_AT_FORWARD = 16u;  // it arrived at the met node's forward port (else at its backward one)
// Rounds of marches: a march that met no node leaves a node where it stopped, marched in the next round. Few
// marches go on past round 0, and fewer each round (the Wuson's default view: 403 nodes of round 0, then 163, 52,
// 23, 9, 7, 2, 2, 1, 1, 1 of rounds 1 to 10; the bunny's: 352, 35), but each round is two passes with a barrier
// after each, which a GPU pays for even when they have nothing to do (about 10 µs a round on an NVIDIA H100 or
// H200). What is left after the last round is traced on on the CPU (extendContour).
INK_CONST uint CONTOUR_ROUNDS = 16u;
// Passes (ContourParams::counts.w): contour_seeds.comp's, then contour_trace.comp's.
INK_CONST uint CONTOUR_PASS_CELLS = 0u;    // per point: each cell's least |n·v| facing the eye and facing away
INK_CONST uint CONTOUR_PASS_PICK = 1u;     // per point: the point that has it wins its side of its cell
INK_CONST uint CONTOUR_PASS_PAIR = 2u;     // per cell: a seed between its winner facing the eye and the nearest
                                           // one facing away around it
INK_CONST uint CONTOUR_PASS_PROJECT = 3u;  // per seed: projected onto the contour, a node
INK_CONST uint CONTOUR_PASS_MARCH = 4u;    // per node of the round: its forward march to the next node; in round 0
                                           // also each seed node's backward march, beside it
INK_CONST uint CONTOUR_PASS_ENTER = 5u;    // per node made since the last, before each pass of marches: into the grid

// The push constants (std430).
struct ContourParams {
    vec4 eye;      // xyz: the eye (normalized coordinates); w: the predictor step
    vec4 sizes;    // x: the cell size of both grids, y: a seed's farthest projection; z, w: unused
    uvec4 counts;  // x: samples, y: seed-table slots, z: node-grid slots (powers of two), w: the pass
    uvec4 limits;  // x: node capacity, y: vertex capacity, z: the march's round, w: rounds
    uvec4 shape;   // x: seeds or nodes a workgroup traces (the fewest: its subgroups of the largest size, or its
                   // invocations); y, z, w unused
};
INK_ASSERT_SIZE(ContourParams, 80);
INK_ASSERT_OFFSET(ContourParams, counts, 32);

// A point on the contour marches start from (std430). Its two ends ("ports"): forward (along its tangent) and
// backward. A march from one port ends at a port of the node it meets: the backward one when it arrives running
// along that node's tangent, else the forward one.
struct ContourNode {
    vec4 position;   // xyz; w unused
    vec4 normal;     // unit ∇f; w unused
    vec4 tangent;    // unit ∇f × ∇g (g = ∇f·(x − eye)), or its opposite; w unused
    uvec4 state;     // x: the round it marches forward in; y: 1 when that runs against the curve's orientation (it
                     // goes on from a seed's backward march); z: 1 once it is in the node grid; w unused
    uvec4 forward;   // its forward march: x the node met (CONTOUR_NONE), y its first vertex, z its vertex count,
                     // w CONTOUR_* bits
    uvec4 backward;  // likewise its backward march, if it made one
};
INK_ASSERT_SIZE(ContourNode, 96);
INK_ASSERT_OFFSET(ContourNode, state, 48);
INK_ASSERT_OFFSET(ContourNode, forward, 64);
INK_ASSERT_OFFSET(ContourNode, backward, 80);

// A vertex of a march: the node's own position first, then each corrected step before the node it met (std430).
struct ContourVertex {
    vec4 position;  // xyz; w unused
    vec4 normal;    // unit ∇f; w unused
};
INK_ASSERT_SIZE(ContourVertex, 32);

// What the passes count (std430).
struct ContourCounters {
    uint nodes;        // nodes made (may pass the capacity: those past it were not stored)
    uint vertices;     // vertices written (likewise)
    uint evaluations;  // of the surface (f, ∇f and the Hessian)
    uint lost;         // seeds whose cell found no slot in the table, nodes none in the grid
    uvec4 march;       // the march pass's VkDispatchIndirectCommand (and a pad)
    uvec4 project;     // the projection pass's, over the listed seeds
    uint listed;       // seeds listed (CONTOUR_LIST)
    uint marching;     // the nodes when the last CONTOUR_PASS_ENTER ran: those the next marches march from
    uint pad0, pad1;   // (std430: uvec4 alignment)
};
INK_ASSERT_SIZE(ContourCounters, 64);
INK_ASSERT_OFFSET(ContourCounters, march, 16);
INK_ASSERT_OFFSET(ContourCounters, project, 32);

// The descriptor set's own bindings (after the refinement's surface, 0 and 8-11).
INK_CONST uint CONTOUR_SAMPLES = 12u;   // Point[]: the drawn points (the seeds)
INK_CONST uint CONTOUR_SEEDS = 13u;     // uint[], CONTOUR_SEED_SLOT a slot: cell key, the least |n·v| (float bits)
                                        // facing the eye and away, the points that have them
INK_CONST uint CONTOUR_NODES = 14u;     // ContourNode[]
INK_CONST uint CONTOUR_GRID = 15u;      // uint[] per slot: cell key, CONTOUR_GRID_NODES node indices
INK_CONST uint CONTOUR_VERTICES = 16u;  // ContourVertex[]
INK_CONST uint CONTOUR_COUNTERS = 17u;  // ContourCounters
INK_CONST uint CONTOUR_LIST = 18u;      // vec4[]: the seeds (CONTOUR_PASS_PAIR), xyz, to project

INK_END

#endif
