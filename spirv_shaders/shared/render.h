// The dots' drawing passes (splat.comp, stamp.comp, ink.vert, ink.frag; engine/draw/renderer.cpp): the style, the
// dot list, the frame's counters, the camera's push constants and the descriptor set's bindings (see interface.h).
#ifndef INK_SHARED_RENDER_H
#define INK_SHARED_RENDER_H

#include "interface.h"
#include "limits.h"

INK_BEGIN

// The style (std140).
struct DotStyle {
    vec4 color[2];  // ink (silhouette and front dots), hidden ink (occluded silhouettes)
    vec4 size;      // dot diameter in pixels: silhouette, front, hidden silhouette; w: τ
    vec4 light;     // xyz: unit direction towards the light, in view space or (options.x) model space; w: tone
                    // gamma (0: no tone)
    vec4 tone;      // x: ink density, y: ambient darkness, zw: dot diameter range in pixels
    vec4 options;   // x: 1 when the light is fixed to the model; y: 1 = no dots (the points only splat depth);
                    // z: the screen spacing's radius at darkness 1, pixels (0: no screen spacing); w: 1 / its
                    // grid's cell side, pixels (spacing.comp)
};
INK_ASSERT_SIZE(DotStyle, 96);
INK_ASSERT_OFFSET(DotStyle, size, 32);
INK_ASSERT_OFFSET(DotStyle, options, 80);

// A dot that passed class, tone and frustum (splat.comp), for stamp.comp (std430). The dot list is a uvec4
// header (workgroups, 1, 1, dots: stamp.comp's indirect dispatch, one workgroup per GROUP_SIZE dots), then the dots.
struct Dot {
    vec2 pixel;    // the centre, in pixels
    float z;       // normalized depth
    uint cls;      // SILHOUETTE or FRONT | DOT_BACK_SIDE | the point's index in its set << 3; stamp.comp then makes
                   // it the class | the visible class (BACK: hidden) << 2 | the index << 4, for
                   // PointRenderer::drawnPoints
    float radius;  // the screen spacing's radius, pixels: no two spaced dots closer than the smaller radius
    uint key;      // the point's rank's bits: the lower key wins a conflict (then the lower point index)
    uint state;    // SPACE_* below
    float scale;   // the dot's diameter over its class's: above 1 where the screen spacing keeps fewer dots than
                   // the tone asks, for want of candidates (SPACE_SUPPLY_KEPT), so that they carry its ink
    vec2 along;    // a silhouette dot's half stroke along the outline, pixels (SILHOUETTE_REACH; before PASS_REACH
                   // the direction and the reach); 0: a round dot
};
INK_ASSERT_SIZE(Dot, 40);
INK_ASSERT_OFFSET(Dot, z, 8);
INK_ASSERT_OFFSET(Dot, cls, 12);
INK_ASSERT_OFFSET(Dot, radius, 16);
INK_ASSERT_OFFSET(Dot, state, 24);
INK_ASSERT_OFFSET(Dot, scale, 28);
INK_ASSERT_OFFSET(Dot, along, 32);

// A dot enclosed on four sides by nearer splats within this many splat radii (at most SPLAT_HOLE_CELLS depth cells)
// lies in a hole in the splats, behind the surface (stamp.comp's enclosed()).
INK_CONST float SPLAT_HOLE = 3.0;
INK_CONST int SPLAT_HOLE_CELLS = 16;

// A silhouette dot is a stroke along the outline's screen tangent that joins it to the nearest silhouette dots
// ahead and behind, each within SILHOUETTE_REACH splat radii and SILHOUETTE_REACH_MAX of its diameters (splat.comp
// sets the reach, stamp.comp's PASS_OUTLINE and PASS_REACH find them), as wide as the dot (stamp.comp, and the SVG
// and PDF). The band |n·v| < τ is about 2τ/κ_r of surface across the outline (κ_r the radial curvature), so where
// the surface is tightly curved (a trunk, an ear, a leg) its points lie far apart along the outline, and round dots
// left it dotted or grey. Joined only to dots that are there, a stroke never overshoots the outline's end or a
// tight turn, and a lone dot (a few points turned nearly edge-on, off any outline) stays round
// (docs/algorithm.md §4). Six, not four: along the rounded edges of a low-poly mesh's fit (assimp's Spider's legs)
// and an elephant's ear the band's dots lie up to six diameters apart, and four left those outlines dashed.
INK_CONST float SILHOUETTE_REACH = 6.0;
INK_CONST float SILHOUETTE_REACH_MAX = 6.0;

// The silhouette band's width on the screen, in silhouette dot diameters. The band |n·v| < τ lies within
// τ² / (2 κ_r) of the outline (κ_r the radial curvature: across the outline, n·v grows as κ_r times the distance
// along the surface, which the screen sees foreshortened to κ_r d² / 2), so where the surface turns away slowly
// (κ_r small: a cylinder seen along its axis, a face seen edge on) it was a wide band of silhouette dots, their
// strokes a black wedge (CGAL's dragknob.off, ball.ply's faces). splat.comp takes τ down to √(2 κ_r w) there, w
// this width at the point's depth; elsewhere τ stays.
INK_CONST float SILHOUETTE_BAND = 1.0;

// shape.comp: the shape operator of every drawn point, once after the refinement (engine/draw/renderer.cpp).
INK_CONST uint SHAPE_GROUP_SIZE = 64u;
INK_CONST uint SHAPE_POINTS = 12u;  // Point[]: the drawn points (storage)
INK_CONST uint SHAPE_OUT = 13u;     // vec4[]: per point (S11, S12, S22, 1) in tangentFrame(normal); 0: unknown

// A dot's state in the screen spacing (spacing.comp, engine/draw/screen_spacing.h): FIXED dots take no part
// (silhouettes, hidden ones, dots drawn without tone), the others start OPEN and end ACCEPTED (drawn) or REJECTED; a
// dot still OPEN after the last round is not drawn.
INK_CONST uint SPACE_FIXED = 0u;
INK_CONST uint SPACE_OPEN = 1u;
INK_CONST uint SPACE_ACCEPTED = 2u;
INK_CONST uint SPACE_REJECTED = 3u;
// Rounds of the spacing: each accepts every open dot that no open dot of a lower key within its radius blocks.
// Measured (docs/algorithm.md §4): every dot is decided by the 4th round on the bunny, cow, armadillo, knot and
// torus at 1024², 2048², three times the ink and both styles (3 rounds leave 1 or 2 open); 6 keeps two spare.
INK_CONST uint SPACE_ROUNDS = 6u;
// The screen spacing's supply: the tone asks for SPACE_SUPPLY candidates a dot (renderer.cpp's k), and where the
// point set cannot give SPACE_SUPPLY_KEPT a dot (a dark tone, a surface turned away), the dots are spaced for the
// density it can give, each larger by up to SPACE_MAX_SCALE in diameter to carry the tone's ink.
INK_CONST float SPACE_SUPPLY = 6.0;
INK_CONST float SPACE_SUPPLY_KEPT = 5.0;
INK_CONST float SPACE_MAX_SCALE = 2.0;
// A dot's spacing radius is at most this many grid cells (the lightest tones), which bounds its search.
INK_CONST float SPACE_MAX_CELLS = 8.0;
// The relaxation after the spacing (spacing.comp, PASS_RELAX): SPACE_RELAX_ROUNDS Jacobi steps push each accepted
// dot away from the accepted dots within SPACE_RELAX_REACH times its radius, by SPACE_RELAX_STEP of the summed
// push (δ · (R² − d²) / R² a neighbour at offset δ, distance d, reach R), at most SPACE_RELAX_STEP_MAX radii a step,
// half its room to the nearest (so that no two come closer than SPACE_RELAX_FLOOR of their smaller radius) and
// SPACE_RELAX_MAX radii in all; a dot whose neighbours' centroid lies farther than SPACE_RELAX_EDGE reaches (the
// edge of its region: an outline, a tone's end) or that has fewer than 3 neighbours stays. The greedy leaves the
// dots just over a radius apart; the steps spread them towards the even spacing of the tone (docs/algorithm.md §4).
INK_CONST uint SPACE_RELAX_ROUNDS = 3u;
INK_CONST float SPACE_RELAX_REACH = 1.7;
INK_CONST float SPACE_RELAX_STEP = 0.28;
INK_CONST float SPACE_RELAX_STEP_MAX = 0.25;
INK_CONST float SPACE_RELAX_MAX = 0.5;
INK_CONST float SPACE_RELAX_EDGE = 0.35;
INK_CONST float SPACE_RELAX_FLOOR = 0.9;
// What the push constants' counts.w asks of stamp.comp and spacing.comp (the pass; PASS_CLAIM_* and PASS_DECIDE:
// | the round << 8; PASS_RELAX: | the step << 8).
INK_CONST uint PASS_VISIBILITY = 0u;    // stamp.comp: classes after occlusion, spaced dots OPEN
INK_CONST uint PASS_STAMP = 1u;         // stamp.comp: the visible, accepted dots into the coverage
INK_CONST uint PASS_CLAIM_KEY = 2u;     // spacing.comp: each cell's lowest open key
INK_CONST uint PASS_CLAIM_POINT = 3u;   // spacing.comp: of the dots with that key, the lowest point index
INK_CONST uint PASS_CLAIM_DOT = 4u;     // spacing.comp: that dot's list index, the cell's owner
INK_CONST uint PASS_DECIDE = 5u;        // spacing.comp: owners no lower owner blocks are accepted
INK_CONST uint PASS_LIST = 6u;          // spacing.comp: the accepted dots into a list, for the relaxation
INK_CONST uint PASS_RELAX = 7u;         // spacing.comp: each accepted dot's displacement, a step further
INK_CONST uint PASS_PLACE = 8u;         // spacing.comp: each accepted dot moved by its displacement
INK_CONST uint PASS_OUTLINE = 9u;       // stamp.comp: the visible silhouette dots' disks into the coverage
INK_CONST uint PASS_REACH = 10u;        // stamp.comp: each silhouette's stroke to the nearest disks along the outline
INK_CONST uint SPACE_LIST_HEADER = 4u;  // words before the accepted or open dots' lists (spacing.comp)
INK_CONST uint SPACE_BLOCK = 4u;        // the relaxation's blocks of cells a side: a bit a cell in a word
// A smaller grid (a target of a few pixels) is not relaxed: its third plane would not hold the list's header and
// the blocks.
INK_CONST uint SPACE_RELAX_MIN_CELLS = 64u;
INK_CONST uint DOT_LIST_HEADER = 16u;  // bytes before dots[0]

// A point's class (report §5): silhouette |n·v| < τ, front n·v > τ, back n·v < −τ; hidden: an occluded silhouette.
INK_CONST uint SILHOUETTE = 0u;
INK_CONST uint FRONT = 1u;
INK_CONST uint BACK = 2u;
INK_CONST uint HIDDEN = 3u;

// Per frame (std430): the dots drawn (a statistic) and the pixel bounds of their stamps (ink.vert covers just
// those). Also the pen lines' `Drawn` (lines.h).
struct DrawnCounts {
    uvec4 dotCount;  // x: dots
    uvec4 bounds;    // min x, min y, max x, max y of the inked pixels (inclusive); min > max: none
};
INK_ASSERT_SIZE(DrawnCounts, 32);
INK_ASSERT_OFFSET(DrawnCounts, bounds, 16);

// Camera::counts.y's bits.
INK_CONST uint CAMERA_HIDDEN = 1u;  // draw hidden silhouettes
// Sample a disk that spans many depth cells only every few cells, each sample its own cell (splat.comp): for direction
// sampling, whose disks (ρ₀, to bridge the gaps between its lines) are larger than a thin part's curvature. Filled
// completely they hid more of the bunny's visible dots than the holes let through (ray cast, bunny from behind).
INK_CONST uint CAMERA_SPARSE_SPLATS = 2u;
// The set's toned dots are spaced on the page (DotStyle::options.z, spacing.comp): blue-noise stipples only;
// direction sampling's dots lie on lines, the report's look draws every point of a random tone value.
INK_CONST uint CAMERA_SPACED = 4u;
// The set lies on a surface that may be open (GpuRefinement::twoSided): a point facing away is drawn as its other side,
// whose back shows through the openings (a bowl's inside, a one-sided scan from behind); the splat depth hides it
// where the surface in front covers it.
INK_CONST uint CAMERA_TWO_SIDED = 8u;
// A dot of an open surface's back (Dot::cls before stamp.comp's visibility pass; n·v ≤ −τ, what one-sided drawing
// classifies BACK). Besides the plain depth test it is hidden where a depth cell of its own or the eight around,
// written by a front-facing disk (the depth's lowest bit clear), is nearer than the dot taken two push-backs farther:
// the push-back lets a surface's own dots pass its disks, and let a closed part's back show through at folds, thin
// parts and cells no front disk covers (0.6–1.7% more dots on CGAL's bunny, armadillo, fandisk, cow drawn two-sided).
INK_CONST uint DOT_BACK_SIDE = 4u;

// The push constants (std430), within the guaranteed 128 bytes.
struct Camera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32 of the perspective projection (clip.w = −z_view)
    vec4 viewport;    // width, height of the target in pixels; width, height of the depth grid
    vec4 splat;       // x: splat radius, y: push-back (model units; 0: no occlusion); z: tone scale k; w: the
                      // squared distance of the model's centre from the eye (the depth the tone scale is for)
    uvec4 counts;     // x: points in the set; y: CAMERA_* bits; z: the set's first point; w: PASS_*
};
INK_ASSERT_SIZE(Camera, 128);
INK_ASSERT_OFFSET(Camera, projection, 64);
INK_ASSERT_OFFSET(Camera, counts, 112);

// The drawing passes' descriptor set (one per frame and point set).
INK_CONST uint RENDER_DOTS = 0u;          // the dot list (storage)
INK_CONST uint RENDER_STYLE = 1u;         // DotStyle (uniform)
INK_CONST uint RENDER_DRAWN = 2u;         // DrawnCounts (storage)
INK_CONST uint RENDER_DEPTH = 3u;         // uint[]: the splat depth (float bits, half res)
INK_CONST uint RENDER_POINT_TEXELS = 4u;  // the points as RGBA32F texels, two a point (uniform texel buffer)
INK_CONST uint RENDER_COVERAGE = 5u;      // uint[]: the coverage bits (limits.h)
INK_CONST uint RENDER_SPACE_GRID = 6u;    // uint[4 · cells]: the screen spacing's grid (spacing.comp)
INK_CONST uint RENDER_SPACE_OPEN = 7u;    // uint[2 · (4 + points)]: its two lists of open dots (spacing.comp)
INK_CONST uint RENDER_SHAPE_TEXELS = 8u;  // a point's shape operator as an RGBA32F texel (shape.comp), one a point

INK_END

#endif
