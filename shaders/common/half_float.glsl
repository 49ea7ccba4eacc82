// Half floats rounded on the float32 bits (docs/spec.md §19): the packed inputs
// (passes/pack_inputs.comp) and the tile filters' half_result (common/pass_main.glsl, HALF_RESULT)
// store what round_to_half gives, so that the store into an RGBA16F texture is exact and the GPU
// and NumPy agree. NumPy twin: blurlab.twins.inputs.round_to_half.
#include "common/small_float.glsl"

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
