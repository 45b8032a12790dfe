#version 460
// cross_field.comp for models whose patch nodes outgrow one storage buffer: the nodes by device address.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference2 : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define PU_NODES_BY_ADDRESS
#include "lines/cross_field_body.glsl"
