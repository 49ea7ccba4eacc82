#version 450
// Reconstruct of Guertin, McGuire and Nowrouzezahrai, "A Fast and Stable Feature-Aware Motion
// Blur Filter" (HPG 2014), as changes to docs/spec.md §3.4 (docs/guertin2014.md, step by step):
// samples in mirrored pairs around X, alternately along the neighborhood's dominant direction vN
// and along wc, the center's direction blended towards vN's perpendicular as |V[X]| falls to
// 0.5 + gamma (the paper's Eq. 1); each weight scaled by how well the sample's and the center's
// motion align with the sampling direction; the center weighted S / (kappa len(V[X])); each pair's
// weights mirrored against each other by depth and speed. Reads the NeighborMax of the
// direction-keeping dilation (shaders/passes/neighbor_max.glsl with diagonal_reach).
// Compute (16 x 16 threads per group, one per pixel) or fragment (one fragment per pixel).
// NumPy twin: twin.py beside it (reconstruct_guertin2014).
#include "common/tile_filter.glsl"
#include "common/mirrored_pair.glsl"

uniform float gamma;  // the paper's γ: speed over 0.5 px at which wc is V[X]'s own direction
uniform float kappa;  // the paper's κ: the center weight is S / (κ len(V[X]))

// v / |v|, or 0 where v = 0.
vec2 direction(vec2 v) {
    float l = length(v);
    return l > 0.0 ? v / l : vec2(0.0);
}

// The weight of a sample (depth zy, half-vector vy, dist pixels from x) for the sampling
// direction d (unit), before mirroring: the 2012 terms, each scaled by the alignment of the
// motion it spreads with d.
float sample_weight(float dist, float zy, vec2 vy, float zx, vec2 vx, vec2 wc, vec2 d) {
    float f = soft_depth_compare(zx, zy, soft_z);
    float b = soft_depth_compare(zy, zx, soft_z);
    float wa = abs(dot(wc, d));
    float wb = abs(dot(direction(vy), d));
    float shorter = min(len_half(vy), len_half(vx));
    return f * cone(dist, vy) * wb + b * cone(dist, vx) * wa
         + cylinder(dist, vec2(shorter, 0.0)) * max(wa, wb) * 2.0;
}

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = color_at(x);
    ivec2 tile = lookup_tile(x, k, seed, jitter_tiles, tile_grid());
    vec2 vn = neighbor_max_of(tile);
    float vn_length = length(vn);
    if (exits_early(vn_length, early_exit)) return cx;  // nothing moves near here
    int n = sample_count(vn_length, samples, adaptive_samples);

    float kf = float(k);
    float zx;
    vec2 mx;
    depth_motion_at(x, zx, mx);
    vec2 vx = half_velocity(mx, exposure, kf);
    // Eq. 1: wc from vN's perpendicular (on V[X]'s side) to V[X]'s own direction. Where V[X]
    // is parallel to vN (within 1e-3 rad; float rounding would pick the side at random) wp is
    // the left perpendicular (-wn.y, wn.x).
    vec2 wn = vn / vn_length;
    vec2 wp = vec2(-wn.y, wn.x);
    if (dot(wp, vx) < -1e-3 * length(vx)) wp = -wp;
    float vx_length = length(vx);
    float blend = clamp((vx_length - 0.5) / gamma, 0.0, 1.0);
    vec2 wc = normalize(mix(wp, vx_length > 0.0 ? vx / vx_length : wp, blend));

    float weight = float(n) / (kappa * len_half(vx));
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed) - 0.5;
    vec2 center = vec2(x) + 0.5;
    int pairs = n / 2;
    for (int i = 0; i < pairs; ++i) {
        float t = (float(i) + 0.5 + j) / float(pairs);
        vec2 d = (i % 2 == 0) ? wn : wc;  // alternately the neighborhood's and the center's
        vec2 step = d * vn_length * t;
        ivec2 y1 = clamp(ivec2(floor(center + step)), ivec2(0), size - 1);
        ivec2 y2 = clamp(ivec2(floor(center - step)), ivec2(0), size - 1);
        float z1, z2;
        vec2 m1, m2;
        depth_motion_at(y1, z1, m1);
        depth_motion_at(y2, z2, m2);
        vec2 v1 = half_velocity(m1, exposure, kf);
        vec2 v2 = half_velocity(m2, exposure, kf);
        float a1 = sample_weight(length(vec2(y1 - x)), z1, v1, zx, vx, wc, d);
        float a2 = sample_weight(length(vec2(y2 - x)), z2, v2, zx, vx, wc, d);
        mirror_pair(a1, a2, z1, z2, length(v1), length(v2));
        add_pair(a1, a2, color_at(y1), color_at(y2), sum, weight);
    }
    return sum / weight;
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
