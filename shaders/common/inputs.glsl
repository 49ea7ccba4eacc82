// What every pass reads from a G-buffer whose values may not be finite (a frame built from a
// user's arrays, a point crossing the near plane). docs/spec.md §1 conventions; docs/reliability.md
// "Non-finite input". NumPy twin: blurlab.twins.inputs.
//   color  NaN -> 0; +-inf and magnitudes beyond 2^64 -> +-2^64 (per channel);
//   depth  NaN, 0, negative or -inf -> +inf (far: nothing drawn there); +inf stays +inf;
//   motion a vector with a NaN or infinite component -> zero motion; finite components are
//          clamped to +-2^20 pixels (64 x the largest texture: taps land off the image either way).
// NaN and infinity are recognized from the bits: drivers may fold isnan() away under fast math.
// A blur of sanitized inputs sums at most a few thousand weights times 2^64 and stays finite.

const float COLOR_LIMIT = 18446744073709551616.0;  // 2^64
const float MOTION_LIMIT = 1048576.0;              // 2^20 pixels

bool is_nan_bits(float x) {
    return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u;
}

bool is_finite_bits(float x) {
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

vec4 sanitize_color(vec4 c) {
    for (int i = 0; i < 4; ++i) c[i] = is_nan_bits(c[i]) ? 0.0 : clamp(c[i], -COLOR_LIMIT, COLOR_LIMIT);
    return c;
}

float sanitize_depth(float z) {
    return (!is_nan_bits(z) && z > 0.0) ? z : uintBitsToFloat(0x7f800000u);  // +inf
}

vec2 sanitize_motion(vec2 m) {
    if (!is_finite_bits(m.x) || !is_finite_bits(m.y)) return vec2(0.0);
    return clamp(m, -MOTION_LIMIT, MOTION_LIMIT);
}

// RGB at p as the LDR metrics read it (docs/spec.md §6, blurlab.metrics.mse and ssim):
// sanitized, then clipped to [0, 1].
vec3 clipped_colour(sampler2D image, ivec2 p) {
    return clamp(sanitize_color(texelFetch(image, p, 0)).rgb, 0.0, 1.0);
}
