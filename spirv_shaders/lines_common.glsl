// What the pen-line passes share (docs/lines.md): the traced segments, the per-frame lists of those that show,
// the line style and the camera. lines.comp decides per segment and frame what shows; line.vert/line.frag draw
// the list as screen-space capsules (quads with round ends), smooth at any zoom.
#ifndef LINES_COMMON_GLSL
#define LINES_COMMON_GLSL

// Segments fixed in object space, three RGBA32F texels each: (p0, width factor 0), (p1, width factor 1),
// (unit normal, kind bits). Kind bits: KIND_HATCH for hatching, family << 1, level << 2.
layout(binding = 0) uniform samplerBuffer segments;
const uint KIND_HATCH = 1u;

// A segment that shows this frame, in pixels.
struct DrawSegment {
    vec4 ends;     // a.xy, b.xy
    vec2 widths;   // half widths at a and b, in pixels
    uint flags;    // SEG_VISIBLE, SEG_HIDDEN, SEG_INTERIOR
    uint segment;  // its index among the traced segments
};
const uint SEG_VISIBLE = 1u, SEG_HIDDEN = 2u, SEG_INTERIOR = 4u;
layout(std430, binding = 1) buffer DrawList {
    // VkDrawIndirectCommand: 6 vertices a segment, 1 instance, 0, 0. One instance of 6·n vertices, not n instances
    // of 6: a CPU driver (lavapipe) runs the whole vertex and setup path once per instance (5× slower here).
    uvec4 draw;
    DrawSegment list[];
} drawList;

layout(std140, binding = 2) uniform LineStyle {
    vec4 ink;        // contour and hatching ink
    vec4 hiddenInk;  // hidden contours
    vec4 paper;      // halos
    vec4 widths;     // pen widths in pixels: contour, hidden contour, hatching; w: halo width beyond the pen
    vec4 thresholds; // darkness from which each hatching (family, level) shows: (0,0), (0,1), (1,0), (1,1)
    vec4 light;      // xyz: unit direction towards the light (model space, or view space when options.x = 0); w: γ
    vec4 tone;       // x: ink density, y: ambient darkness, z: |n·v| below which hatching is not drawn
    vec4 options;    // x: 1 when the light is fixed to the model; y: 1 = draw hidden contours
} lineStyle;

layout(std430, binding = 3) buffer DepthBuffer { uint depth[]; };
// The frame's coverage and drawn bounds (render_common.glsl), for lines_stamp.comp.
layout(std430, binding = 4) buffer CoverageBuffer { uint coverage[]; };
layout(std430, binding = 5) buffer Drawn {
    uvec4 dotCount;
    uvec4 bounds;
} drawn;

layout(push_constant) uniform LineCamera {
    mat4 view;        // model → view (rigid)
    vec4 projection;  // P00, P11, P22, P32
    vec4 viewport;    // width, height in pixels; width, height of the depth grid
    vec4 params;      // x: push-back (model units); y: pixel scale (supersampling)
    uvec4 counts;     // x: segments; y: draw mode (line.vert): 0 hatching, 1 hidden contours, 2 halos, 3 contours;
                      // lines_stamp.comp: 0 hatching, 1 contours
} cam;

vec4 project(vec3 v) {
    return vec4(cam.projection.x * v.x, cam.projection.y * v.y, cam.projection.z * v.z + cam.projection.w, -v.z);
}

#endif
