// What the pen-line passes share (docs/lines.md): the traced segments, the per-frame lists of those that show,
// the line style and the camera. lines.comp decides per segment and frame what shows; line.vert/line.frag draw
// the list as screen-space capsules (quads with round ends), smooth at any zoom.
#ifndef LINES_COMMON_GLSL
#define LINES_COMMON_GLSL

#include "shared/lines.h"  // DrawSegment, LineStyle, LineCamera, the bindings, KIND_HATCH, SEG_*
#include "shared/render.h"  // DrawnCounts

// Segments fixed in object space, three RGBA32F texels each (shared/lines.h).
layout(binding = LINES_SEGMENTS) uniform samplerBuffer segments;

layout(std430, binding = LINES_DRAW_LIST) buffer DrawList {
    // VkDrawIndirectCommand: 6 vertices a segment, 1 instance, 0, 0. One instance of 6·n vertices, not n instances
    // of 6: a CPU driver (lavapipe) runs the whole vertex and setup path once per instance (5× slower here).
    uvec4 draw;
    DrawSegment list[];
} drawList;

layout(std140, binding = LINES_STYLE) uniform LineStyleBlock { LineStyle lineStyle; };

layout(std430, binding = LINES_DEPTH) buffer DepthBuffer { uint depth[]; };
// The frame's coverage and drawn bounds (render_common.glsl), for lines_stamp.comp.
layout(std430, binding = LINES_COVERAGE) buffer CoverageBuffer { uint coverage[]; };
layout(std430, binding = LINES_DRAWN) buffer DrawnBlock { DrawnCounts drawn; };

layout(push_constant) uniform LineCameraBlock { LineCamera cam; };

// The pen width in pixels of a contour, crease or boundary segment of kind bits `kind`, shown or hidden.
float lineWidth(uint kind, bool visible) {
    if (!visible) return lineStyle.widths.y;
    return (kind & KIND_CREASE) != 0u ? lineStyle.features.x
                                      : ((kind & KIND_BOUNDARY) != 0u ? lineStyle.features.y : lineStyle.widths.x);
}

vec4 project(vec3 v) {
    return vec4(cam.projection.x * v.x, cam.projection.y * v.y, cam.projection.z * v.z + cam.projection.w, -v.z);
}

#endif
