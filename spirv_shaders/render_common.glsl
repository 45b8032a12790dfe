// What the drawing passes share: the point buffer, the style, and the camera (view space, perspective).
#ifndef RENDER_COMMON_GLSL
#define RENDER_COMMON_GLSL

#include "common.glsl"

layout(std430, binding = 0) readonly buffer PointBuffer { Point points[]; };

layout(std140, binding = 1) uniform Style {
    vec4 color[3];  // silhouette, front, hidden silhouette
    vec4 size;      // dot diameter in pixels: silhouette, front, hidden silhouette; w: τ
    vec4 light;     // xyz: unit direction towards the light in view space; w: tone gamma (0: no tone)
    vec4 tone;      // x: ink density, y: ambient darkness, zw: point size range
} style;

layout(push_constant) uniform Camera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32 of the perspective projection (clip.w = −z_view)
    vec4 viewport;    // width, height, 1/width, 1/height in pixels
    vec4 splat;       // x: splat radius, y: push-back, both in model units; z: tone scale k
} cam;

vec4 project(vec3 v) {
    return vec4(cam.projection.x * v.x, cam.projection.y * v.y, cam.projection.z * v.z + cam.projection.w, -v.z);
}

// Report §5: silhouette |n·v| < τ, front n·v > τ, back n·v < −τ; v from the point towards the camera.
const uint SILHOUETTE = 0u, FRONT = 1u, BACK = 2u;
uint classify(float nv) { return abs(nv) < style.size.w ? SILHOUETTE : (nv > 0.0 ? FRONT : BACK); }

const vec4 CULLED = vec4(0.0, 0.0, 2.0, 1.0);  // z > w: clipped away

#endif
