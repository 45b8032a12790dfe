#version 460
#extension GL_GOOGLE_include_directive : require
// Casts the pixel's view ray onto the splat's tangent plane: outside the disk is discarded, inside writes the
// plane's depth pushed back along the ray, so that ink on the visible surface passes the depth test and ink
// behind it fails, even where the front dots leave paper showing.
#include "render_common.glsl"

layout(location = 0) in vec3 centerView;
layout(location = 1) in vec3 normalView;

void main() {
    vec2 ndc = gl_FragCoord.xy * cam.viewport.zw * 2.0 - 1.0;
    vec3 ray = vec3(ndc.x / cam.projection.x, ndc.y / cam.projection.y, -1.0);
    float denom = dot(ray, normalView);
    if (abs(denom) < 1e-6) discard;
    vec3 hit = ray * (dot(centerView, normalView) / denom);
    if (distance(hit, centerView) > cam.splat.x) discard;
    hit += normalize(hit) * cam.splat.y;
    vec4 clip = project(hit);
    gl_FragDepth = clip.z / clip.w;
}
