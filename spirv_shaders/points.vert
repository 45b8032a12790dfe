#version 460
#extension GL_GOOGLE_include_directive : require
// Draws the refinement's points straight from its buffer (indirect draw, no vertex input), classified by the
// report's §5 rule: silhouette |n·v| < τ, front n·v > τ, back n·v < −τ.
#include "common.glsl"

layout(std430, binding = 0) readonly buffer PointBuffer { Point points[]; };
layout(std140, binding = 1) uniform Style {
    vec4 color[3];  // silhouette, front, back
    vec4 size;      // point size in pixels: silhouette, front, back; w: τ
    vec4 light;     // xyz: unit direction towards the light; w: tone gamma (0 = no tone)
    vec4 misc;      // x: draw back points; y, z: point size range
} style;
layout(push_constant) uniform Camera {
    mat4 viewProj;
    vec4 eye;  // camera position in model coordinates
} cam;

layout(location = 0) out vec4 color;

void main() {
    Point p = points[gl_VertexIndex];
    vec3 v = normalize(cam.eye.xyz - p.position);
    float nv = dot(p.normal, v);
    float tau = style.size.w;
    uint cls = abs(nv) < tau ? 0u : (nv > 0.0 ? 1u : 2u);
    bool visible = cls != 2u || style.misc.x > 0.5;
    // Tone (Brazil et al. 2011): a front point is drawn when its fixed random value is below the darkness.
    if (cls == 1u && style.light.w > 0.0) {
        float darkness = pow(1.0 - max(0.0, dot(p.normal, style.light.xyz)), style.light.w);
        visible = visible && p.tone < darkness;
    }
    gl_Position = visible ? cam.viewProj * vec4(p.position, 1.0) : vec4(0.0, 0.0, 2.0, 1.0);  // z > w: clipped
    gl_PointSize = clamp(style.size[cls], style.misc.y, style.misc.z);
    color = style.color[cls];
}
