#version 460
#extension GL_GOOGLE_include_directive : require
// Depth pre-pass of oriented splats (visibility splatting, ALGORITHM.md §6): each point is a disk in its
// tangent plane, drawn as a point sprite large enough to hold the disk's projection.
#include "render_common.glsl"

layout(location = 0) out vec3 centerView;
layout(location = 1) out vec3 normalView;

void main() {
    Point p = points[gl_VertexIndex];
    vec3 c = (cam.view * vec4(p.position, 1.0)).xyz;
    vec3 n = mat3(cam.view) * p.normal;
    // Disks facing away lie behind the front surface of a closed shape; keep a margin for edge-on ones.
    if (dot(n, -normalize(c)) < -0.2 || -c.z <= 0.0) {
        gl_Position = CULLED;
        gl_PointSize = 1.0;
        return;
    }
    centerView = c;
    normalView = n;
    gl_Position = project(c);
    float diameter = 2.0 * cam.splat.x * abs(cam.projection.y) * 0.5 * cam.viewport.y / (-c.z);
    gl_PointSize = clamp(diameter + 2.0, style.tone.z, style.tone.w);
}
