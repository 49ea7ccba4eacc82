// Unsigned small floats, as the packed B10G11R11 texture format holds them (docs/spec.md
// §17.4): a 5-bit exponent (bias 15), no sign, m = 6 mantissa bits (11-bit kind) or 5 (10-bit
// kind). Rounds on the float32 bits, to nearest with ties to an even mantissa, so that the GPU
// and NumPy agree; beyond the largest finite value -> that value, +inf stays, zero, negatives
// and NaN -> 0, below 2^-14 -> denormals (multiples of 2^-(14 + m)).
// NumPy twin: blurlab.twins.small_float. common/half_float.glsl rounds half floats with it
// (m = 10, the sign put back).

const int UF11_MANTISSA = 6;
const int UF10_MANTISSA = 5;

float quantize_small_float(float x, int mantissa_bits) {
    uint bits = floatBitsToUint(x);
    // Normal values (2^-14 <= x, finite, positive), nearly every one, first and in one test:
    // rounding on the bits. Behind three tests it cost the H100 what a half-float filter
    // result saves in bandwidth (docs/benchmarks.md).
    if (bits >= 0x38800000u && bits < 0x7f800000u) {
        uint drop = uint(23 - mantissa_bits);
        uint rounded = ((bits + ((1u << (drop - 1u)) - 1u) + ((bits >> drop) & 1u)) >> drop) << drop;
        float largest = exp2(15.0) * (2.0 - exp2(-float(mantissa_bits)));
        return min(uintBitsToFloat(rounded), largest);
    }
    if (bits == 0x7f800000u) return x;                        // +inf
    if ((bits & 0x80000000u) != 0u || bits > 0x7f800000u) return 0.0;  // negative or NaN
    float scale = exp2(float(14 + mantissa_bits));
    return roundEven(x * scale) / scale;  // below 2^-14: denormals
}
