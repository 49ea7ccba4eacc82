#version 450
// engine_eevee step 3, docs/spec.md §17.2: the gather. The tile read is moved by up to ±1/4 tile
// per axis; under EARLY_EXIT px of motion there the pixel keeps its color. Otherwise `samples`
// taps along the tile's prev half-motion (the pixels whose way back to t0 crosses X) and as many
// against its next half-motion (those whose way on to t1 crosses X), each weighted by §3.4's
// terms on the same side's half-motions with soft_z = 1 / depth_scale; X itself weighs
// 1 / max(|prev|, |next|, 0.5). Compute, one invocation per pixel.
// NumPy twin: twin.engine_eevee (twin.py).
#include "common/eevee.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/jittered_tile.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion_sides;
layout(binding = 3) uniform sampler2D dilated;
uniform int tile_size;
uniform int samples;
uniform float max_blur;
uniform float depth_scale;
uniform float exposure;
uniform uint seed;

const uvec2 JITTER_SALTS = uvec2(0x3C6EF372u, 0xA54FF53Au);

vec4 gather_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec4 tile_motion = jittered_tile_texel(dilated, x, tile_size, seed, JITTER_SALTS);
    vec4 reach = vec4(clamp_length(tile_motion.xy, max_blur), clamp_length(tile_motion.zw, max_blur));
    if (max(length(reach.xy), length(reach.zw)) < EARLY_EXIT) return cx;

    float soft_z = 1.0 / depth_scale;
    float zx = sanitize_depth(texelFetch(depth, x, 0).x);
    vec4 mx = texelFetch(motion_sides, x, 0);
    vec2 own[2] = vec2[2](clamp_length(scaled_motion(mx.xy, exposure), max_blur),
                          clamp_length(scaled_motion(mx.zw, exposure), max_blur));
    float weight = 1.0 / max(max(length(own[0]), length(own[1])), 0.5);
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed);
    vec2 center = vec2(x) + 0.5;
    vec2 directions[2] = vec2[2](reach.xy, -reach.zw);
    for (int side = 0; side < 2; ++side) {
        vec2 vx = own[side];
        for (int i = 0; i < samples; ++i) {
            float t = (float(i) + j) / float(samples);
            ivec2 y = clamp(ivec2(floor(center + directions[side] * t)), ivec2(0), size - 1);
            vec4 my = texelFetch(motion_sides, y, 0);
            vec2 vy = clamp_length(scaled_motion(side == 0 ? my.xy : my.zw, exposure), max_blur);
            float zy = sanitize_depth(texelFetch(depth, y, 0).x);
            float dist = length(vec2(y - x));
            float a = soft_depth_compare(zx, zy, soft_z) * cone(dist, vy)
                    + soft_depth_compare(zy, zx, soft_z) * cone(dist, vx)
                    + cylinder(dist, vy) * cylinder(dist, vx) * 2.0;
            weight += a;
            sum += a * sanitize_color(texelFetch(color, y, 0));
        }
    }
    return sum / weight;
}

#define PASS_AT gather_at
#include "common/pass_main.glsl"
