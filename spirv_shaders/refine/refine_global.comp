#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_vote : require
// The refinement with the global HRBF in double (--fit global): see refine_body.glsl.
#define HRBF_GLOBAL 1
#include "refine/refine_body.glsl"
