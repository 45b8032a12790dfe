// The body of shape.comp (and shape_large.comp), once per drawn point after the refinement and the selection
// (engine/draw/renderer.cpp): the surface's shape operator at the point, S = P H P / |∇F| (H the Hessian of the
// partition of unity, P the projection onto the tangent plane), in tangentFrame(the point's normal):
// (S11, S12, S22, 1); 0 where it is not finite. splat.comp reads the radial curvature κ_r = r̂ᵀ S r̂ from it, for
// the silhouette band's width on the screen (SILHOUETTE_BAND).
#ifndef SHAPE_BODY_GLSL
#define SHAPE_BODY_GLSL

#include "common.glsl"
#include "shared/render.h"
#include "refine/pu_hrbf.glsl"

layout(local_size_x = SHAPE_GROUP_SIZE) in;

layout(std430, binding = SHAPE_POINTS) readonly buffer Points { Point points[]; };
layout(std430, binding = SHAPE_OUT) writeonly buffer Shapes { vec4 shapes[]; };
// x: the draw's first point, y: its points, z: this dispatch's first (a dispatch at most the device's groups)
layout(push_constant) uniform Range { uvec4 range; };

void main() {
    uint i = range.z + gl_GlobalInvocationID.x;  // the shape of the draw's i-th point
    if (i >= range.y) return;
    Point p = points[range.x + i];
    vec3 grad;
    mat3 H;
    puEvalHessian(p.position, grad, H);
    float g = length(grad);
    vec3 t1, t2;
    tangentFrame(p.normal, t1, t2);
    vec4 s = vec4(dot(t1, H * t1), dot(t1, H * t2), dot(t2, H * t2), g) / g;
    shapes[i] = g > 0.0 && !any(isnan(s)) && !any(isinf(s)) ? s : vec4(0.0);
}

#endif
