#version 450
// The box gather (common/box_gather.glsl) as a pass of its own, shaped as a method's, for
// tests/test_shader_pass.py (what reflect() lists, errors that name the shader).
#include "common/box_gather.glsl"

#define PASS_AT box_gather_at
#include "common/pass_main.glsl"
