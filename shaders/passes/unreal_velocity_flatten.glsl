#version 450
// engine_unreal step 1, docs/spec.md §17.5: the half-vector E·M/2, its length clamped to R, in
// polar 11-bit codes, and the depth as a 10-bit float (common/polar_fixed_point.glsl), the engine's
// 11:11:10 texel kept exactly in RGBA32F. Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.unreal.velocity_flatten.
#include "common/velocity_setup.glsl"
#include "common/polar_fixed_point.glsl"

uniform float exposure;
uniform float radius;  // R, pixels

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, imageSize(velocity)))) return;
    vec2 v = motion_at(x) * exposure * 0.5;
    float z = float10(depth_at(x));
    imageStore(velocity, x, vec4(polar_codes(v, radius), z, 0.0));
}
