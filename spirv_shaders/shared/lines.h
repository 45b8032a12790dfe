// The pen lines' passes (lines.comp, lines_stamp.comp, line.vert, line.frag; engine/lines/strokes.cpp): the drawn
// segments, the line style, the camera's push constants and the descriptor set's bindings (see interface.h).
#ifndef INK_SHARED_LINES_H
#define INK_SHARED_LINES_H

#include "interface.h"
#include "limits.h"

INK_BEGIN

// Traced segments, fixed in object space: LINE_TEXELS RGBA32F texels each, (p0, w0), (p1, w1), (unit normal (a
// crease's: the mean of its faces' unit normals, of length cos(α/2)), kind bits: limits.h's KIND_HATCH | family <<
// HATCH_FAMILY_SHIFT | level << HATCH_LEVEL_SHIFT, or KIND_CREASE | KIND_FACED, KIND_BOUNDARY, a contour's
// KIND_OCCLUDED, and the segments before and after it in its stroke). w: the pen's width factor at the end (hatching
// tapers), a crease's or boundary's standoff there (PenStroke::standoff, model units).
INK_CONST uint LINE_TEXELS = 3u;

// A segment that shows this frame, in pixels (std430). The draw list is a uvec4 header (VkDrawIndirectCommand: 6
// vertices a segment, 1 instance, 0, 0), then the segments.
struct DrawSegment {
    vec4 ends;     // a.xy, b.xy
    vec2 widths;   // half widths at a and b, in pixels
    uint flags;    // SEG_VISIBLE, SEG_HIDDEN, SEG_INTERIOR (limits.h)
    uint segment;  // its index among the traced segments (SEG_INDEX_MASK), and SEG_RAW_* (limits.h)
};
INK_ASSERT_SIZE(DrawSegment, 32);
INK_ASSERT_OFFSET(DrawSegment, widths, 16);
INK_ASSERT_OFFSET(DrawSegment, flags, 24);
INK_ASSERT_OFFSET(DrawSegment, segment, 28);

// The line style (std140).
struct LineStyle {
    vec4 ink;         // contour and hatching ink
    vec4 hiddenInk;   // hidden contours
    vec4 paper;       // halos
    vec4 widths;      // pen widths in pixels: contour, hidden contour, hatching; w: halo width beyond the pen
    vec4 thresholds;  // darkness from which each hatching (family, level) shows: (0,0), (0,1), (1,0), (1,1)
    vec4 diagonal;    // x, y: the same for the third, diagonal family (2,0), (2,1); z: its |n·v| below which it
                      // is not drawn; w unused
    vec4 light;       // xyz: unit direction towards the light (model space, or view space when options.x = 0); w: γ
    vec4 tone;        // x: ink density, y: ambient darkness, z: |n·v| below which hatching is not drawn,
                      // w: hatching whose tone shows it over a shorter run of its stroke than this fraction of the
                      // image's shorter side is not drawn
    vec4 options;     // x: 1 when the light is fixed to the model; y: 1 = draw hidden contours
    vec4 features;    // pen widths in pixels: x crease, y boundary lines; z: the median window of the visibility
                      // of contour, crease and boundary lines, either way along the stroke (fraction of the
                      // shorter side)
};
INK_ASSERT_SIZE(LineStyle, 160);
INK_ASSERT_OFFSET(LineStyle, widths, 48);
INK_ASSERT_OFFSET(LineStyle, diagonal, 80);
INK_ASSERT_OFFSET(LineStyle, options, 128);

// The push constants (std430).
struct LineCamera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32
    vec4 viewport;    // width, height in pixels; width, height of the depth grid
    vec4 params;      // x: push-back (model units); y: pixel scale (supersampling); z: 1 on an open surface
                      // (hatching shows where it faces away too, as the dots do: gpu::CAMERA_TWO_SIDED)
    uvec4 counts;     // x: segments; y: draw mode (line.vert): 0 hatching, 1 hidden contours, 2 halos, 3 contours;
                      // lines_stamp.comp: 0 hatching, 1 contours (and crease and boundary lines)
};
INK_ASSERT_SIZE(LineCamera, 128);
INK_ASSERT_OFFSET(LineCamera, counts, 112);

// The pen lines' descriptor set (one per frame and kind).
INK_CONST uint LINES_SEGMENTS = 0u;   // the traced segments (uniform texel buffer)
INK_CONST uint LINES_DRAW_LIST = 1u;  // the draw list (storage)
INK_CONST uint LINES_STYLE = 2u;      // LineStyle (uniform)
INK_CONST uint LINES_DEPTH = 3u;      // the dots' splat depth (storage)
INK_CONST uint LINES_COVERAGE = 4u;   // the frame's coverage bits (storage)
INK_CONST uint LINES_DRAWN = 5u;      // the frame's DrawnCounts (storage)
INK_CONST uint LINES_BINDINGS = 6u;

INK_END

#endif
