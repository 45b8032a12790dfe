#version 460
#extension GL_GOOGLE_include_directive : require
// The ink: points classified as silhouette, front or back (report §5), thinned by tone (Brazil et al. 2011),
// tested against the splat depth. With HIDDEN_LINES, only silhouettes are drawn, where the splats hide them.
#include "render_common.glsl"

layout(constant_id = 0) const bool HIDDEN_LINES = false;

layout(location = 0) out vec4 color;

void main() {
    Point p = points[gl_VertexIndex];
    vec3 c = (cam.view * vec4(p.position, 1.0)).xyz;
    vec3 n = mat3(cam.view) * p.normal;
    float nv = dot(n, -normalize(c));
    uint cls = classify(nv);
    bool visible = HIDDEN_LINES ? cls == SILHOUETTE : cls != BACK;
    if (cls == FRONT && style.light.w > 0.0) {
        // Draw a point when its fixed random value is below the darkness, so density follows shading and a
        // point keeps its state while the light on it does not change.
        float lit = max(0.0, dot(n, style.light.xyz));
        float darkness = (style.tone.y + pow(1.0 - lit, style.light.w)) * style.tone.x * cam.splat.z;
        visible = visible && p.tone < darkness;
    }
    gl_Position = visible && -c.z > 0.0 ? project(c) : CULLED;
    uint slot = HIDDEN_LINES ? 2u : cls;
    gl_PointSize = clamp(style.size[slot], style.tone.z, style.tone.w);
    color = style.color[slot];
}
