// A velocity in polar form with 11-bit codes, and a depth rounded to a 10-bit float: the
// 11:11:10 texel of docs/spec.md §17.5 step 1 (engine_unreal), kept exactly in RGBA32F.
//   length  c_l = floor(min(|v|/R, 1)·2047 + 1/2), read as c_l/2047·R
//   angle   c_a = floor(u·2048 + 1/2) mod 2048, u = atan2(v.y, v.x)/2π in [0, 1), read as
//           c_a·2π/2048 (0 for v = 0)
//   depth   the unsigned 10-bit float of R11G11B10F's blue channel (5 exponent, 5 mantissa
//           bits): rounded to nearest even, below 2^-14 read as 2^-14, above 64512 as +inf
// NumPy twin: blurlab.twins.polar_fixed_point.

const float LENGTH_CODE_MAX = 2047.0;
const float ANGLE_CODES = 2048.0;
const float TWO_PI = 6.28318530717958647692;
const float FLOAT10_MIN = 6.103515625e-05;  // 2^-14, the smallest normal 10-bit float
const float FLOAT10_MAX = 64512.0;          // 2^15·(1 + 31/32)

vec2 polar_codes(vec2 v, float radius) {
    float n = length(v);
    float c_l = floor(min(n / radius, 1.0) * LENGTH_CODE_MAX + 0.5);
    if (n == 0.0) return vec2(c_l, 0.0);
    float u = atan(v.y, v.x) / TWO_PI;
    if (u < 0.0) u += 1.0;
    float c_a = floor(u * ANGLE_CODES + 0.5);
    return vec2(c_l, c_a >= ANGLE_CODES ? 0.0 : c_a);
}

vec2 decode_polar(vec2 codes, float radius) {
    float angle = codes.y * (TWO_PI / ANGLE_CODES);
    return codes.x / LENGTH_CODE_MAX * radius * vec2(cos(angle), sin(angle));
}

// z > 0 or +inf (a sanitized depth).
float float10(float z) {
    float c = max(z, FLOAT10_MIN);
    if (!(c <= FLOAT10_MAX)) return uintBitsToFloat(0x7f800000u);  // +inf
    int e;
    float m = frexp(c, e);  // c = m·2^e, m in [0.5, 1)
    float q = ldexp(roundEven(m * 64.0), e - 6);
    return q > FLOAT10_MAX ? uintBitsToFloat(0x7f800000u) : q;
}
