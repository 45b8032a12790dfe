#version 460
// shape.comp for models whose patch nodes outgrow one storage buffer: the nodes by device address.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference2 : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define PU_NODES_BY_ADDRESS
#include "draw/shape_body.glsl"
