#version 450
// Reconstruct, docs/spec.md §3.4: S samples along the neighborhood's dominant half-vector vN, each
// weighted by depth order and by whether the sample's or the center's blur covers the other.
// Compute (16 x 16 threads per group, one per pixel) or fragment (one fragment per pixel).
// NumPy twin: twin.py beside it (reconstruct_mcguire2012).
#include "common/tile_filter.glsl"

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = color_at(x);
    ivec2 tile = lookup_tile(x, k, seed, jitter_tiles, tile_grid());
    vec2 vn = neighbor_max_of(tile);
    if (exits_early(length(vn), early_exit)) return cx;  // nothing moves near here
    int n = sample_count(length(vn), samples, adaptive_samples);

    float kf = float(k);
    float zx;
    vec2 mx;
    depth_motion_at(x, zx, mx);
    vec2 vx = half_velocity(mx, exposure, kf);
    float weight = 1.0 / len_half(vx);
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed) - 0.5;
    vec2 center = vec2(x) + 0.5;
    int skip = (n % 2 == 1) ? (n - 1) / 2 : -1;  // the center itself is X
    for (int i = 0; i < n; ++i) {
        if (i == skip) continue;
        float t = -1.0 + 2.0 * (float(i) + j + 1.0) / float(n + 1);
        ivec2 y = clamp(ivec2(floor(center + vn * t)), ivec2(0), size - 1);
        float zy;
        vec2 my;
        depth_motion_at(y, zy, my);
        vec2 vy = half_velocity(my, exposure, kf);
        float dist = length(vec2(y - x));
        float f = soft_depth_compare(zx, zy, soft_z);
        float b = soft_depth_compare(zy, zx, soft_z);
        float a = f * cone(dist, vy) + b * cone(dist, vx)
                + cylinder(dist, vy) * cylinder(dist, vx) * 2.0;
        weight += a;
        sum += a * color_at(y);
    }
    return sum / weight;
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
