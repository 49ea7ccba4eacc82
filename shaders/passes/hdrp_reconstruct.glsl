#version 450
// engine_hdrp step 5, docs/spec.md §17.4: the path chosen per tile. Early-out tiles keep C; the
// others take n = clamp(floor(L), 1, samples) taps along the neighbourhood's longest velocity
// v (length L), at t = (i + j)/n - 1/2 of it; a fast tile averages them with C(X) with equal
// weights, a slow one weighs them by §3.4's cones and cylinders on the taps' radii (half their
// stored lengths) and the soft depth comparison with extent depth_comparison_extent on the
// stored depths. Compute, one invocation per pixel. NumPy twin: blurlab.twins.hdrp.engine_hdrp.
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/small_float.glsl"
#include "common/polar_small_float.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;
layout(binding = 2) uniform sampler2D neighborhood;
uniform int samples;
uniform float depth_comparison_extent;
uniform int tile;  // px
uniform uint seed;

const float EARLY_OUT = 0.0, FAST = 1.0;

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec4 tile_info = texelFetch(neighborhood, x / tile, 0);
    if (tile_info.w == EARLY_OUT) return cx;
    vec2 vmax = polar_decode(tile_info.xy);
    int n = int(clamp(floor(tile_info.x), 1.0, float(samples)));
    float j = rand(uint(x.x), uint(x.y), seed);
    vec2 center = vec2(x) + 0.5;
    bool fast = tile_info.w == FAST;
    vec4 own = texelFetch(velocity, x, 0);
    vec2 r_x = vec2(own.x * 0.5, 0.0);  // radius: half the stored length
    float weight = fast ? 1.0 : 1.0 / max(r_x.x, 0.5);
    vec4 sum = cx * weight;
    for (int i = 0; i < n; ++i) {
        float t = (float(i) + j) / float(n) - 0.5;
        ivec2 y = clamp(ivec2(floor(center + vmax * t)), ivec2(0), size - 1);
        vec4 cy = sanitize_color(texelFetch(color, y, 0));
        if (fast) {
            sum += cy;
            weight += 1.0;
            continue;
        }
        vec4 other = texelFetch(velocity, y, 0);
        vec2 r_y = vec2(other.x * 0.5, 0.0);
        float dist = length(vec2(y - x));
        float f = soft_depth_compare(own.z, other.z, depth_comparison_extent);
        float b = soft_depth_compare(other.z, own.z, depth_comparison_extent);
        float a = f * cone(dist, r_y) + b * cone(dist, r_x) +
                  cylinder(dist, r_y) * cylinder(dist, r_x) * 2.0;
        sum += a * cy;
        weight += a;
    }
    return sum / weight;
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
