// What the engines' velocity passes share (step 1 of engine_unity §17.3, engine_hdrp §17.4,
// engine_unreal §17.5 and engine_godot §17.10 in docs/spec.md): the G-buffer's depth and motion
// in, read by the rules of common/inputs.glsl; one invocation per pixel, 16 x 16 a work group;
// the pixel's velocity texel out to `velocity` (RGBA32F, holding whatever codes the engine packs).
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D depth;
layout(binding = 1) uniform sampler2D motion;

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D velocity;

float depth_at(ivec2 x) {
    return sanitize_depth(texelFetch(depth, x, 0).x);
}

vec2 motion_at(ivec2 x) {
    return sanitize_motion(texelFetch(motion, x, 0).xy);
}
