#version 450
// Packed filter inputs, docs/spec.md §19: once per frame, the G-buffer read by the rules of
// common/inputs.glsl and then clamped into half-float range, written as two RGBA16F textures
// that the tile filters read with PACKED_INPUTS: colour, and (motion.x, motion.y, depth, 0).
// An image format has no three-channel half-float layout, so w is written 0 and left unread.
// NumPy twin: blurlab.twins.inputs.pack_half.
#include "common/inputs.glsl"
#include "common/small_float.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion;
layout(binding = 0, rgba16f) uniform writeonly image2D packed_color;
layout(binding = 1, rgba16f) uniform writeonly image2D packed_motion_depth;

const float HALF_MAX = 65504.0;           // the largest finite half float
const float HALF_MIN_NORMAL = 6.1035156e-5;  // 2^-14, the smallest normal half float
const int HALF_MANTISSA = 10;

// x (sanitized, within +-HALF_MAX, or infinite) rounded to the nearest half float, ties to even,
// as a float32: a half is common/small_float.glsl's 5-bit-exponent float with 10 mantissa bits
// and a sign, so |x| is rounded there and x's sign bit put back (-0 stays -0). The conversion
// that imageStore then makes is exact whatever rounding the driver uses: llvmpipe's rounds ties
// towards zero (2051 -> 2050, not 2052).
float round_to_half(float x) {
    float rounded = quantize_small_float(abs(x), HALF_MANTISSA);
    return uintBitsToFloat(floatBitsToUint(rounded) | (floatBitsToUint(x) & 0x80000000u));
}

vec4 round_to_half(vec4 v) {
    for (int i = 0; i < 4; ++i) v[i] = round_to_half(v[i]);
    return v;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(packed_color)))) return;
    vec4 c = clamp(sanitize_color(texelFetch(color, p, 0)), -HALF_MAX, HALF_MAX);
    vec2 m = clamp(sanitize_motion(texelFetch(motion, p, 0).xy), -HALF_MAX, HALF_MAX);
    // A finite depth stays finite, positive and normal in half (0, or a subnormal that a driver
    // may flush to 0, would read as "nothing drawn"); the background's +inf stays +inf.
    float z = sanitize_depth(texelFetch(depth, p, 0).x);
    if (is_finite_bits(z)) z = clamp(z, HALF_MIN_NORMAL, HALF_MAX);
    imageStore(packed_color, p, round_to_half(c));
    imageStore(packed_motion_depth, p, round_to_half(vec4(m, z, 0.0)));
}
