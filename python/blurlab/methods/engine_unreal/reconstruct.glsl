#version 450
// engine_unreal step 4, docs/spec.md §17.5: the path chosen per 16 x 16 tile by its class
// (one compute work group is one tile, so the branch is the same across a group). Skip: C.
// Otherwise taps/2 mirrored pairs at X ± t·v_max, t = (i + j)/(taps/2), v_max the tile's
// longest reaching velocity. Fast: every tap weighs 1. Slow: a tap weighs the soft depth
// split (extent depth_extent) of whether X's own blur or the tap's reaches it
// (spread = clamp(1 + length - distance, 0, 1)), at most 1, and each pair takes the weight of
// its nearer and faster tap; the weight the taps do not take goes to C.
// Compute, one invocation per pixel. NumPy twin: twin.py, engine_unreal.
#include "common/inputs.glsl"
#include "common/random.glsl"
#include "common/polar_fixed_point.glsl"
#include "common/mirrored_pair.glsl"
#include "common/unreal.glsl"
#include "common/depth_spread.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;
layout(binding = 2) uniform sampler2D neighbors;
uniform int taps;  // the quality level's sample count
uniform float depth_extent;
uniform float radius;  // R, pixels
uniform uint seed;

// Tap texel s (codes, depth) at `dist` pixels from X, whose depth is z_x and blur radius len_x.
float tap_weight(vec4 s, float dist, float z_x, float len_x) {
    float len_y = s.x / LENGTH_CODE_MAX * radius;
    return depth_spread_weight(z_x, len_x, s.z, len_y, dist, depth_extent);
}

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec4 tile = texelFetch(neighbors, x / TILE, 0);
    if (tile.w == TILE_SKIP) return cx;
    bool slow = tile.w == TILE_SLOW;
    vec2 vmax = decode_polar(tile.xy, radius);
    vec4 own = texelFetch(velocity, x, 0);
    float len_x = own.x / LENGTH_CODE_MAX * radius;
    int pairs = taps / 2;
    float j = rand(uint(x.x), uint(x.y), seed);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < pairs; ++i) {
        ivec2 y1, y2;
        mirrored_taps(x, vmax, i, j, pairs, size, y1, y2);
        float a1 = 1.0, a2 = 1.0;
        if (slow) {
            vec4 s1 = texelFetch(velocity, y1, 0);
            vec4 s2 = texelFetch(velocity, y2, 0);
            a1 = tap_weight(s1, length(vec2(y1 - x)), own.z, len_x);
            a2 = tap_weight(s2, length(vec2(y2 - x)), own.z, len_x);
            mirror_pair(a1, a2, s1.z, s2.z, s1.x, s2.x);
        }
        vec4 c1 = sanitize_color(texelFetch(color, y1, 0));
        add_pair(a1, a2, c1, sanitize_color(texelFetch(color, y2, 0)), sum, weight);
    }
    return left_to_center(sum, weight, cx, pairs);
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
