#version 460
#extension GL_GOOGLE_include_directive : require
// Decides, once per point and frame, whether and how its dot is drawn: classification (report §5), tone
// (Brazil et al. 2011), and occlusion against the splat depth. Survivors are appended to the visible list,
// whose count is the indirect draw's vertex count; the draw then touches only the dots that show.
#include "render_common.glsl"

layout(local_size_x = 64) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cam.counts.x) return;
    Point p = fetchPoint(cam.counts.z + i);
    vec3 c = (cam.view * vec4(p.position, 1.0)).xyz;
    if (-c.z <= 1e-6) return;
    vec3 n = mat3(cam.view) * p.normal;
    uint cls = classify(dot(n, -normalize(c)));
    if (cls == BACK) return;
    if (cls == FRONT && style.light.w > 0.0) {
        // Drawn when its fixed tone value is below the darkness: density follows shading, and a dot keeps its
        // state while the light on it does not change.
        float lit = max(0.0, dot(n, style.light.xyz));
        float darkness = (style.tone.y + pow(1.0 - lit, style.light.w)) * style.tone.x * cam.splat.z;
        if (p.tone >= darkness) return;
    }
    vec4 clip = project(c);
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0))) || ndc.z > 1.0) return;
    if (cam.splat.x > 0.0) {
        vec2 grid = cam.viewport.zw;
        ivec2 cell = clamp(ivec2((ndc.xy * 0.5 + 0.5) * grid), ivec2(0), ivec2(grid) - 1);
        bool occluded = ndc.z > uintBitsToFloat(depth[cell.y * int(grid.x) + cell.x]);
        if (occluded) {
            if (cls != SILHOUETTE || (cam.counts.y & 1u) == 0u) return;
            cls = HIDDEN;
        }
    }
    uint slot = atomicAdd(draw.x, 1u);
    visible[slot] = (cam.counts.z + i) | (cls << 30);
}
