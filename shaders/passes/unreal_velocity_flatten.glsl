#version 450
// engine_unreal step 1, docs/spec.md §17.5: the half-vector E·M/2, its length clamped to R, in
// polar 11-bit codes, and the depth as a 10-bit float (common/polar_fixed_point.glsl), the engine's
// 11:11:10 texel kept exactly in RGBA32F. Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.unreal.velocity_flatten.
#include "common/inputs.glsl"
#include "common/polar_fixed_point.glsl"

layout(binding = 0) uniform sampler2D depth;
layout(binding = 1) uniform sampler2D motion;
uniform float exposure;
uniform float radius;  // R, pixels

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D velocity;

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, imageSize(velocity)))) return;
    vec2 v = sanitize_motion(texelFetch(motion, x, 0).xy) * exposure * 0.5;
    float z = float10(sanitize_depth(texelFetch(depth, x, 0).x));
    imageStore(velocity, x, vec4(polar_codes(v, radius), z, 0.0));
}
