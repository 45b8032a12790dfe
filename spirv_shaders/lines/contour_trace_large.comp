#version 460
// contour_trace.comp for models whose patch nodes outgrow one storage buffer: the nodes by device address.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_buffer_reference2 : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define PU_NODES_BY_ADDRESS
#include "lines/contour_trace_body.glsl"
