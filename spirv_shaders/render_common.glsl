// What the drawing passes share: the point buffer, the style, and the camera (view space, perspective).
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

#include "common.glsl"

layout(std430, binding = 0) readonly buffer PointBuffer { Point points[]; };

layout(std140, binding = 1) uniform Style {
    vec4 color[4];  // silhouette, front, back (unused), hidden silhouette
    vec4 size;      // dot diameter in pixels: silhouette, front, hidden silhouette; w: τ
    vec4 light;     // xyz: unit direction towards the light in view space; w: tone gamma (0: no tone)
    vec4 tone;      // x: ink density, y: ambient darkness, zw: point size range
} style;

// Per frame and set: the visible dots (point index | class << 30), and the splat depth (float bits, half res).
layout(std430, binding = 2) buffer VisibleBuffer {
    uvec4 draw;  // vertexCount, instanceCount, firstVertex, firstInstance
    uint visible[];
};
layout(std430, binding = 3) buffer DepthBuffer { uint depth[]; };

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

// The depth grid is the target at half resolution: one cell per 2×2 pixels.
const float DEPTH_CELL = 2.0;

#endif
