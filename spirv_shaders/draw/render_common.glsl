// What the drawing passes share: the points, the style, the per-frame buffers and the camera (view space,
// perspective). On a CPU driver every instruction of a shader runs for every batch of lanes, masked or not, so
// the passes narrow the work down with lists rather than branches: splat.comp runs over every point,
// stamp.comp over the few dots that may show.
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

#include "common.glsl"
#include "shared/render.h"

layout(std140, binding = RENDER_STYLE) uniform StyleBlock { DotStyle style; };

// Per frame and set: the dots that passed class, tone and frustum (splat.comp), for stamp.comp to test for
// occlusion and stamp. `dispatch` is stamp.comp's indirect dispatch, one workgroup per GROUP_SIZE dots.
layout(std430, binding = RENDER_DOTS) buffer DotList {
    uvec4 dispatch;  // workgroups, 1, 1, dots
    Dot dots[];
} list;

// Per frame: the dots drawn and the bounds of their stamps (shared/render.h), and the splat depth (float
// bits, half res).
layout(std430, binding = RENDER_DRAWN) buffer DrawnBlock { DrawnCounts drawn; };
layout(std430, binding = RENDER_DEPTH) buffer DepthBuffer { uint depth[]; };

// Per frame: the ink coverage of every target pixel, four bits a pixel, eight pixels a word (pixel i in word
// i / 8 at bit 4·(i mod 8); shared/limits.h). stamp.comp sets it for the dots, lines_stamp.comp for pen lines
// where they are stamped in compute; ink.frag turns it into colour: a contour's ink over a halo's paper over the
// dots' and hatching's ink over hidden ink.
layout(std430, binding = RENDER_COVERAGE) buffer CoverageBuffer { uint coverage[]; };

// Pixel i's four coverage bits.
uint coverageBits(uint i) { return (coverage[i >> COVERAGE_SHIFT] >> ((i & 7u) * COVERAGE_BITS)) & 15u; }

// The same points as RGBA32F texels, two a point: texel fetches are vectorized gathers on CPU drivers, where
// per-point storage-buffer loads become one scalar load per lane and component.
layout(binding = RENDER_POINT_TEXELS) uniform samplerBuffer pointTexels;

Point fetchPoint(uint i) {
    vec4 a = texelFetch(pointTexels, int(2u * i)), b = texelFetch(pointTexels, int(2u * i + 1u));
    return Point(a.xyz, floatBitsToUint(a.w), b.xyz, b.w);
}

// Each point's shape operator in its tangent frame (shape.comp): (S11, S12, S22, 1), or 0 where unknown (a global
// fit's points, the report's dense HRBF in double: its τ stays the style's).
layout(binding = RENDER_SHAPE_TEXELS) uniform samplerBuffer shapeTexels;

layout(push_constant) uniform CameraBlock { Camera cam; };

vec4 project(vec3 v) {
    return vec4(cam.projection.x * v.x, cam.projection.y * v.y, cam.projection.z * v.z + cam.projection.w, -v.z);
}

// Report §5 (the classes are shared/render.h's): silhouette |n·v| < τ, front n·v > τ, back n·v < −τ; v from
// the point towards the camera. τ: the style's, or less where the band would be wider than SILHOUETTE_BAND.
uint classify(float nv, float tau) { return abs(nv) < tau ? SILHOUETTE : (nv > 0.0 ? FRONT : BACK); }


#endif
