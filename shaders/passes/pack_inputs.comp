#version 450
// Packed filter inputs, docs/spec.md §19: once per frame, the G-buffer read by the rules of
// common/inputs.glsl and then clamped into half-float range, written as two RGBA16F textures
// that the tile filters read with PACKED_INPUTS: colour, and (motion.x, motion.y, depth, 0).
// An image format has no three-channel half-float layout, so w is written 0 and left unread.
// NumPy twin: blurlab.twins.inputs.pack_half.
#include "common/gbuffer.glsl"
#include "common/half_float.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba16f) uniform writeonly image2D packed_color;
layout(binding = 1, rgba16f) uniform writeonly image2D packed_motion_depth;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(packed_color)))) return;
    vec4 c = clamp(color_at(p), -HALF_MAX, HALF_MAX);
    vec2 m = clamp(motion_at(p), -HALF_MAX, HALF_MAX);
    // A finite depth stays finite, positive and normal in half (0, or a subnormal that a driver
    // may flush to 0, would read as "nothing drawn"); the background's +inf stays +inf.
    float z = depth_at(p);
    if (is_finite_bits(z)) z = clamp(z, HALF_MIN_NORMAL, HALF_MAX);
    imageStore(packed_color, p, round_to_half(c));
    imageStore(packed_motion_depth, p, round_to_half(vec4(m, z, 0.0)));
}
