#version 460
#extension GL_GOOGLE_include_directive : require
// The ink: the dots cull.comp found visible, round, sized and coloured by class.
#include "render_common.glsl"

layout(location = 0) out vec4 color;

void main() {
    uint entry = visible[gl_VertexIndex];
    uint cls = entry >> 30;
    Point p = fetchPoint(entry & 0x3FFFFFFFu);
    gl_Position = project((cam.view * vec4(p.position, 1.0)).xyz);
    uint sizeSlot = cls == HIDDEN ? 2u : cls;
    gl_PointSize = clamp(style.size[sizeSlot], style.tone.z, style.tone.w);
    color = style.color[cls];
}
