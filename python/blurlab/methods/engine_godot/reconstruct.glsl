#version 450
// engine_godot step 3, docs/spec.md §17.10: `taps` samples centred on X along the neighbourhood's
// half-vector vN (the blur is centred on the pixel), t_i = -1 + 2(i + j + 1)/(taps + 1), each
// weighted as §3.4 weighs a sample, with the two depths compared at the tap's time t/2 of the
// shutter: z + (t/2)·dz (the depth velocity). Half-vectors are the velocity's, clamped to k
// (so velocities to twice the tile size). Compute, one invocation per pixel.
// NumPy twin: twin.py, reconstruct.
#include "common/inputs.glsl"
#include "common/random.glsl"
#include "common/mcguire2012.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;  // (V, depth, dz) from velocity.glsl
layout(binding = 2) uniform sampler2D neighbor_max;
uniform int k;
uniform float exposure;
uniform float soft_z;
uniform int taps;  // the quality preset's sample count
uniform uint seed;

// The depth of texel s (V, z, dz) at shutter time tau (a fraction of the shutter from its
// centre); a point at infinity stays there.
float depth_at(vec4 s, float tau) {
    return isinf(s.z) ? s.z : s.z + tau * s.w * exposure;
}

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec2 vn = texelFetch(neighbor_max, x / k, 0).xy;
    if (length(vn) <= 0.5 + 0.01) return cx;  // nothing moves near here
    vec4 sx = texelFetch(velocity, x, 0);
    vec2 vx = half_velocity(sanitize_motion(sx.xy), exposure, float(k));
    float weight = 1.0 / len_half(vx);
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed) - 0.5;
    vec2 center = vec2(x) + 0.5;
    for (int i = 0; i < taps; ++i) {
        float t = -1.0 + 2.0 * (float(i) + j + 1.0) / float(taps + 1);
        ivec2 y = clamp(ivec2(floor(center + vn * t)), ivec2(0), size - 1);
        vec4 sy = texelFetch(velocity, y, 0);
        vec2 vy = half_velocity(sanitize_motion(sy.xy), exposure, float(k));
        float dist = length(vec2(y - x));
        float zx = depth_at(sx, 0.5 * t), zy = depth_at(sy, 0.5 * t);
        float f = soft_depth_compare(zx, zy, soft_z);
        float b = soft_depth_compare(zy, zx, soft_z);
        float a = f * cone(dist, vy) + b * cone(dist, vx)
                + cylinder(dist, vy) * cylinder(dist, vx) * 2.0;
        weight += a;
        sum += a * sanitize_color(texelFetch(color, y, 0));
    }
    return sum / weight;
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
