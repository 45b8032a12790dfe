// What the drawing passes share: the points, the style, the per-frame buffers and the camera (view space,
// perspective). On a CPU driver every instruction of a shader runs for every batch of lanes, masked or not, so
// the passes narrow the work down with lists rather than branches: splat.comp runs over every point,
// stamp.comp over the few dots that may show.
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

#include "common.glsl"

layout(std140, binding = 1) uniform Style {
    vec4 color[2];  // ink (silhouette and front dots), hidden ink (occluded silhouettes)
    vec4 size;      // dot diameter in pixels: silhouette, front, hidden silhouette; w: τ
    vec4 light;     // xyz: unit direction towards the light, in view space or (options.x) model space; w: tone
                    // gamma (0: no tone)
    vec4 tone;      // x: ink density, y: ambient darkness, zw: dot diameter range in pixels
    vec4 options;   // x: 1 when the light is fixed to the model; y: 1 = no dots (the points only splat depth)
} style;

// Per frame and set: the dots that passed class, tone and frustum (splat.comp), for stamp.comp to test for
// occlusion and stamp. `dispatch` is stamp.comp's indirect dispatch, one workgroup per GROUP_SIZE dots.
struct Dot {
    vec2 pixel;  // the centre, in pixels
    float z;     // normalized depth
    uint cls;    // SILHOUETTE or FRONT | the point's index in its set << 2; stamp.comp then makes it the class
                 // | the visible class (BACK: hidden) << 2 | the index << 4, for PointRenderer::drawnPoints
};
layout(std430, binding = 0) buffer DotList {
    uvec4 dispatch;  // workgroups, 1, 1, dots
    Dot dots[];
} list;
const uint GROUP_SIZE = 256u;

// Per frame: the dots drawn (a statistic) and the pixel bounds of their stamps (ink.vert covers just those),
// and the splat depth (float bits, half res).
layout(std430, binding = 2) buffer Drawn {
    uvec4 dotCount;  // x: dots
    uvec4 bounds;    // min x, min y, max x, max y of the inked pixels (inclusive); min > max: none
} drawn;
layout(std430, binding = 3) buffer DepthBuffer { uint depth[]; };

// Per frame: the ink coverage of every target pixel, four bits a pixel, eight pixels a word (pixel i in word
// i / 8 at bit 4·(i mod 8)). stamp.comp sets it for the dots, lines_stamp.comp for pen lines where they are
// stamped in compute; ink.frag turns it into colour: a contour's ink over a halo's paper over the dots' and
// hatching's ink over hidden ink.
layout(std430, binding = 5) buffer CoverageBuffer { uint coverage[]; };
const uint INK_BIT = 1u, HIDDEN_BIT = 2u, HALO_BIT = 4u, CONTOUR_BIT = 8u;
const uint COVERAGE_SHIFT = 3u, COVERAGE_BITS = 4u;  // pixel i: word i >> 3, bits 4·(i & 7)

// The same points as RGBA32F texels, two a point: texel fetches are vectorized gathers on CPU drivers, where
// per-point storage-buffer loads become one scalar load per lane and component.
layout(binding = 4) uniform samplerBuffer pointTexels;

Point fetchPoint(uint i) {
    vec4 a = texelFetch(pointTexels, int(2u * i)), b = texelFetch(pointTexels, int(2u * i + 1u));
    return Point(a.xyz, floatBitsToUint(a.w), b.xyz, b.w);
}

layout(push_constant) uniform Camera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32 of the perspective projection (clip.w = −z_view)
    vec4 viewport;    // width, height of the target in pixels; width, height of the depth grid
    vec4 splat;       // x: splat radius, y: push-back (model units), 0: no occlusion; z: tone scale k
    uvec4 counts;     // x: points in the set; y: 1 = draw hidden silhouettes; z: the set's first point
} cam;

vec4 project(vec3 v) {
    return vec4(cam.projection.x * v.x, cam.projection.y * v.y, cam.projection.z * v.z + cam.projection.w, -v.z);
}

// Report §5: silhouette |n·v| < τ, front n·v > τ, back n·v < −τ; v from the point towards the camera.
const uint SILHOUETTE = 0u, FRONT = 1u, BACK = 2u, HIDDEN = 3u;
uint classify(float nv) { return abs(nv) < style.size.w ? SILHOUETTE : (nv > 0.0 ? FRONT : BACK); }


#endif
