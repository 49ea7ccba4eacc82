#version 450
// engine_unreal5 step 5, docs/spec.md §17.7: the path chosen per 16 x 16 tile by its class (one
// compute work group is one tile). Skip: C. Otherwise a line of mirrored pairs along the tile's
// longest velocity, and for gather_2 a second line along its second direction. A line whose
// longest half-vector is L px takes P = clamp(ceil(2L), 1, taps/2) pairs at X ± t·v, t =
// (i + j)/P; where half_res_gather is on and its taps lie HALF_RES_SPACING px apart or more,
// they read the half-size colour. Uniform: every tap weighs 1. Gather: the soft depth split of
// whether X's blur or the tap's reaches it (common/depth_spread.glsl), each blur's radius its
// length along the line, and the pairs' mirror. Each line adds its taps' mean, Σa·C/2P, and
// its coverage, Σa/2P; the coverage the lines leave goes to C, and where they cover more than
// the whole pixel the sum is normalised. Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.unreal5.engine_unreal5.
#include "common/inputs.glsl"
#include "common/random.glsl"
#include "common/polar_fixed_point.glsl"
#include "common/mirrored_pair.glsl"
#include "common/depth_spread.glsl"
#include "common/unreal.glsl"
#include "common/unreal5.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;
layout(binding = 2) uniform sampler2D neighbors;
layout(binding = 3) uniform sampler2D half_color;
uniform int taps;  // the quality level's sample count: the most taps on one line
uniform int half_res_gather;
uniform float depth_extent;
uniform float radius;  // R, pixels
uniform uint seed;

const float PAIR_SPACING = 0.5;      // px of a line's longest half-vector per pair
const float HALF_RES_SPACING = 8.0;  // px between taps from which they read half_color

// Blur radius along the unit `axis` of the pixel whose velocity texel is s.
float along(vec4 s, vec2 axis) {
    return abs(dot(decode_polar(s.xy, radius), axis));
}

// One line's taps at X: adds their mean Σa·C/2P to shares and Σa/2P to coverage.
void gather_line(ivec2 x, vec2 codes, bool uniform_tile, float j, inout vec4 shares,
                 inout float coverage) {
    ivec2 size = textureSize(color, 0);
    vec2 v = decode_polar(codes, radius);
    float angle = codes.y * (TWO_PI / ANGLE_CODES);
    vec2 axis = vec2(cos(angle), sin(angle));
    float len = codes.x / LENGTH_CODE_MAX * radius;
    int pairs = int(clamp(ceil(len / PAIR_SPACING), 1.0, float(taps / 2)));
    bool from_half = half_res_gather == 1 && len / float(pairs) >= HALF_RES_SPACING;
    vec4 own = texelFetch(velocity, x, 0);
    float len_x = along(own, axis);
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < pairs; ++i) {
        float t = (float(i) + j) / float(pairs);
        ivec2 y1 = clamp(ivec2(floor(center + t * v)), ivec2(0), size - 1);
        ivec2 y2 = clamp(ivec2(floor(center - t * v)), ivec2(0), size - 1);
        float a1 = 1.0, a2 = 1.0;
        if (!uniform_tile) {
            vec4 s1 = texelFetch(velocity, y1, 0);
            vec4 s2 = texelFetch(velocity, y2, 0);
            a1 = depth_spread_weight(own.z, len_x, s1.z, along(s1, axis), length(vec2(y1 - x)),
                                     depth_extent);
            a2 = depth_spread_weight(own.z, len_x, s2.z, along(s2, axis), length(vec2(y2 - x)),
                                     depth_extent);
            mirror_pair(a1, a2, s1.z, s2.z, s1.x, s2.x);
        }
        vec4 c1 = from_half ? texelFetch(half_color, y1 / 2, 0)
                            : sanitize_color(texelFetch(color, y1, 0));
        vec4 c2 = from_half ? texelFetch(half_color, y2 / 2, 0)
                            : sanitize_color(texelFetch(color, y2, 0));
        add_pair(a1, a2, c1, c2, sum, weight);
    }
    float n = float(2 * pairs);
    shares += sum / n;
    coverage += weight / n;
}

vec4 reconstruct_at(ivec2 x) {
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec4 tile = texelFetch(neighbors, x / TILE, 0);
    if (tile.w == CLASS_SKIP) return cx;
    float j = rand(uint(x.x), uint(x.y), seed);
    vec4 shares = vec4(0.0);
    float coverage = 0.0;
    gather_line(x, tile.xy, tile.w == CLASS_UNIFORM, j, shares, coverage);
    if (tile.w == CLASS_GATHER_2) gather_line(x, unpack_codes(tile.z), false, j, shares, coverage);
    return (shares + max(1.0 - coverage, 0.0) * cx) / max(coverage, 1.0);
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
