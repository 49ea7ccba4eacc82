// my_tent (spec.md beside this file); NumPy twin: twin.py. An HLSL compute shader:
// blurlab translates it to GLSL 4.50 (glslang, SPIRV-Cross) and binds its resources by name.
Texture2D<float4> color;
Texture2D<float4> motion;
RWTexture2D<float4> result;
int taps;
float scale;

// How blurlab reads NaN and inf (its shaders/common/inputs.glsl): NaN colour is 0, colour
// beyond 2^64 clamps; a motion with a NaN or inf component is none, the rest clamps to 2^20.
static const float COLOR_LIMIT = 18446744073709551616.0;
static const float MOTION_LIMIT = 1048576.0;

bool is_nan_bits(float x) { return (asuint(x) & 0x7fffffffu) > 0x7f800000u; }
bool is_finite_bits(float x) { return (asuint(x) & 0x7f800000u) != 0x7f800000u; }

float4 sanitize_color(float4 c) {
    [unroll] for (int i = 0; i < 4; ++i)
        c[i] = is_nan_bits(c[i]) ? 0.0 : clamp(c[i], -COLOR_LIMIT, COLOR_LIMIT);
    return c;
}

float2 sanitize_motion(float2 m) {
    if (!is_finite_bits(m.x) || !is_finite_bits(m.y)) return float2(0.0, 0.0);
    return clamp(m, -MOTION_LIMIT, MOTION_LIMIT);
}

[numthreads(16, 16, 1)]
void main(uint3 id : SV_DispatchThreadID) {
    uint width, height;
    color.GetDimensions(width, height);
    if (id.x >= width || id.y >= height) return;
    int2 size = int2(width, height);
    float2 m = sanitize_motion(motion.Load(int3(id.xy, 0)).xy) * scale;
    float2 center = float2(id.xy) + 0.5;
    float4 sum = 0.0;
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {
        float s = (float(i) + 0.5) / float(taps) - 0.5;
        float weight = 1.0 - 2.0 * abs(s);
        int2 y = clamp(int2(floor(center - s * m)), int2(0, 0), size - 1);
        sum += weight * sanitize_color(color.Load(int3(y, 0)));
        total += weight;
    }
    result[id.xy] = sum / total;
}
