// The G-buffer as docs/spec.md §10.1 reads it, texel by texel: colour, depth and motion at
// bindings 0-2, every read sanitized by the rules of common/inputs.glsl. Shared by the passes
// that read it so: the tile filters (common/tile_filter_inputs.glsl, unless PACKED_INPUTS),
// gather_pixel, and pack_inputs, which packs it for PACKED_INPUTS.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion;

vec4 color_at(ivec2 p) {
    return sanitize_color(texelFetch(color, p, 0));
}

float depth_at(ivec2 p) {
    return sanitize_depth(texelFetch(depth, p, 0).x);
}

vec2 motion_at(ivec2 p) {
    return sanitize_motion(texelFetch(motion, p, 0).xy);
}
