// A velocity stored polar in two unsigned 11-bit floats (docs/spec.md §17.4): its length in
// pixels and its direction as a fraction of a turn, u = atan2(v.y, v.x)/2π + 1/2 in [0, 1]
// (u = 1/2 for zero motion, whose direction GLSL's atan leaves undefined). The length needs no
// scale (the format reaches 65024); the angle's step is at most 2^-7 turn (2.8°, for u >= 1/2).
// Needs common/small_float.glsl. NumPy twin: blurlab.twins.polar_small_float.

const float TURN = 6.28318530717958647692;

vec2 polar_codes(vec2 v) {
    float turn = (v.x == 0.0 && v.y == 0.0) ? 0.5 : atan(v.y, v.x) / TURN + 0.5;
    return vec2(quantize_small_float(length(v), UF11_MANTISSA),
                quantize_small_float(turn, UF11_MANTISSA));
}

vec2 polar_decode(vec2 codes) {
    float angle = (codes.y - 0.5) * TURN;
    return codes.x * vec2(cos(angle), sin(angle));
}
