#version 450
// engine_unity step 1, docs/spec.md §17.3: the half-vector E·M/2 clamped to the largest blur
// radius R, mapped from [-R, R] to [0, 1], and the linear depth Z/far clamped to [0, 1], each
// as a 10-bit code (the engine's 10:10:10:2 buffer; kept here in RGBA32F, the codes exact).
// Compute, one invocation per pixel. NumPy twin: twin.velocity_setup (twin.py).
#include "common/velocity_setup.glsl"
#include "unity.glsl"

uniform float exposure;
uniform float far;
uniform float radius;  // R, pixels

float quantize(float x) {
    return floor(clamp(x, 0.0, 1.0) * CODE_MAX + 0.5);
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, imageSize(velocity)))) return;
    vec2 v = motion_at(x) * exposure * 0.5;
    float n = length(v);
    if (n > radius) v *= radius / n;
    float z = min(depth_at(x) / far, 1.0);
    vec2 c = vec2(quantize((v.x / radius + 1.0) * 0.5), quantize((v.y / radius + 1.0) * 0.5));
    imageStore(velocity, x, vec4(c, quantize(z), 0.0));
}
