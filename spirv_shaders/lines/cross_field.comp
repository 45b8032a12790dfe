#version 460
#extension GL_GOOGLE_include_directive : require
// The hatching's cross field on the device (cross_field_body.glsl).
#include "lines/cross_field_body.glsl"
