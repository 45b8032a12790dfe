// The dots' drawing passes (splat.comp, stamp.comp, ink.vert, ink.frag; engine/renderer.cpp): the style, the
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
    vec4 options;   // x: 1 when the light is fixed to the model; y: 1 = no dots (the points only splat depth)
};
INK_ASSERT_SIZE(DotStyle, 96);
INK_ASSERT_OFFSET(DotStyle, size, 32);
INK_ASSERT_OFFSET(DotStyle, options, 80);

// A dot that passed class, tone and frustum (splat.comp), for stamp.comp (std430). The dot list is a uvec4
// header (workgroups, 1, 1, dots: stamp.comp's indirect dispatch, one workgroup per GROUP_SIZE dots), then the dots.
struct Dot {
    vec2 pixel;  // the centre, in pixels
    float z;     // normalized depth
    uint cls;    // SILHOUETTE or FRONT | the point's index in its set << 2; stamp.comp then makes it the class
                 // | the visible class (BACK: hidden) << 2 | the index << 4, for PointRenderer::drawnPoints
};
INK_ASSERT_SIZE(Dot, 16);
INK_ASSERT_OFFSET(Dot, z, 8);
INK_ASSERT_OFFSET(Dot, cls, 12);
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

// The push constants (std430), within the guaranteed 128 bytes.
struct Camera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32 of the perspective projection (clip.w = −z_view)
    vec4 viewport;    // width, height of the target in pixels; width, height of the depth grid
    vec4 splat;       // x: splat radius, y: push-back (model units), 0: no occlusion; z: tone scale k
    uvec4 counts;     // x: points in the set; y: 1 = draw hidden silhouettes; z: the set's first point
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

INK_END

#endif
