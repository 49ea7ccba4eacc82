#version 450
// engine_hdrp step 5, docs/spec.md §17.4: the path chosen per tile. Early-out tiles keep C; the
// others take n = clamp(floor(L), 1, samples) taps along the neighbourhood's longest velocity
// v (length L), at t = (i + j)/n - 1/2 of it; a fast tile averages them with C(X) with equal
// weights, a slow one weighs them by §3.4's cones and cylinders on the taps' radii (half their
// stored lengths) and the soft depth comparison with extent depth_comparison_extent on the
// stored depths. Compute, one invocation per pixel: without OVER_LIST over the whole image,
// each pixel taking its tile's class; with OVER_LIST one 16 x 16 work group per tile of one
// class's list (docs/spec.md §9.3), the class being LIST_CLASS, covering the tile in 16 x 16
// blocks. Both write the same bits. NumPy twin: twin.engine_hdrp (twin.py).
#ifdef OVER_LIST
#define TILE_LISTS_READ 1
#define TILE_LIST_SAMPLER 3
#include "common/tile_lists.glsl"
#endif
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

// Pixel x of a tile of class `kind` whose neighbourhood texel is tile_info.
vec4 reconstruct_class(ivec2 x, vec4 tile_info, float kind) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    if (kind == EARLY_OUT) return cx;
    vec2 vmax = polar_decode(tile_info.xy);
    int n = int(clamp(floor(tile_info.x), 1.0, float(samples)));
    float j = rand(uint(x.x), uint(x.y), seed);
    vec2 center = vec2(x) + 0.5;
    bool fast = kind == FAST;
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

#ifdef OVER_LIST
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D result;

void main() {
    ivec2 grid = textureSize(neighborhood, 0);
    ivec2 t = listed_tile(grid.x);
    vec4 tile_info = texelFetch(neighborhood, t, 0);
    ivec2 size = textureSize(color, 0);
    for (int by = 0; by < tile; by += 16) {
        for (int bx = 0; bx < tile; bx += 16) {
            ivec2 x = t * tile + ivec2(bx, by) + ivec2(gl_LocalInvocationID.xy);
            if (all(lessThan(x, size)))
                imageStore(result, x, reconstruct_class(x, tile_info, float(LIST_CLASS)));
        }
    }
}
#else
vec4 reconstruct_at(ivec2 x) {
    vec4 tile_info = texelFetch(neighborhood, x / tile, 0);
    return reconstruct_class(x, tile_info, tile_info.w);
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
#endif
