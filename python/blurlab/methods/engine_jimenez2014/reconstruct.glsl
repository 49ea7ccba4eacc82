#version 450
// engine_jimenez2014, docs/spec.md §17.8: the reconstruction of Jimenez 2014 on §3's NeighborMax
// vN. Pixels whose vN is at most 0.51 px keep C. Otherwise P = max(samples/2, 1) mirrored pairs
// at X ± t·vN, t = (i + j)/P, j the talk's interleaved gradient noise at X's center (moved by
// 5.588238 px per frame, frame = seed mod 64); each tap weighs the soft depth split of whether
// X's blur or the tap's reaches it (common/depth_spread.glsl, extent soft_z), each pair takes the
// weight of its nearer and faster tap, and the weight the taps do not take stays with C: the
// foreground's alpha. Compute or fragment. NumPy twin: twin.py beside it.
#include "common/tile_filter_inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/mirrored_pair.glsl"
#include "common/depth_spread.glsl"

layout(binding = 3) uniform sampler2D neighbor_max;

const float EARLY_EXIT = 0.5 + 0.01;

// `precise`: no fused multiply-add, so every driver rounds as the twin does.
float interleaved_gradient_noise(ivec2 x) {
    precise float shift = 5.588238 * float(seed % 64u);
    precise vec2 p = vec2(x) + 0.5 + shift;
    precise float s = 0.06711056 * p.x + 0.00583715 * p.y;
    s = s - floor(s);
    precise float t = 52.9829189 * s;
    return t - floor(t);
}

float length_at(ivec2 p) {
    return length(half_velocity(motion_at(p), exposure, float(k)));
}

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = color_at(x);
    vec2 vn = texelFetch(neighbor_max, x / k, 0).xy;
    if (length(vn) <= EARLY_EXIT) return cx;
    float z_x = depth_at(x);
    float len_x = length_at(x);
    int pairs = max(samples / 2, 1);
    float j = interleaved_gradient_noise(x);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < pairs; ++i) {
        ivec2 y1, y2;
        mirrored_taps(x, vn, i, j, pairs, size, y1, y2);
        float z1 = depth_at(y1);
        float z2 = depth_at(y2);
        float len1 = length_at(y1), len2 = length_at(y2);
        float a1 = depth_spread_weight(z_x, len_x, z1, len1, length(vec2(y1 - x)), soft_z);
        float a2 = depth_spread_weight(z_x, len_x, z2, len2, length(vec2(y2 - x)), soft_z);
        mirror_pair(a1, a2, z1, z2, len1, len2);
        add_pair(a1, a2, color_at(y1), color_at(y2), sum, weight);
    }
    return left_to_center(sum, weight, cx, pairs);
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
