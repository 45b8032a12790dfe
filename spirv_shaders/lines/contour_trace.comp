#version 460
#extension GL_GOOGLE_include_directive : require
#include "lines/contour_trace_body.glsl"
