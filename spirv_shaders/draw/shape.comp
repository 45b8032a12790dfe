#version 460
#extension GL_GOOGLE_include_directive : require
// Each drawn point's shape operator, for the silhouette band (shape_body.glsl).
#include "draw/shape_body.glsl"
