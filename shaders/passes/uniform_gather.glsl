#version 450
// The uniform class of the tile classification (docs/classify_and_steps.md): docs/spec.md §3.4
// with every pixel taken to move by vN = NeighborMax at one depth, so that
// V[X] = V[Y] = vN and f = b = 1: the weight of a tap at distance d is
// a = 2·cone(d, vN) + 2·cyl(d, vN)², the center's 1/len(vN); only colors are read (one fetch
// per tap instead of three). Same taps and jitter as the full filter, so where motion is truly
// uniform and depth even, both give the same image. The tap loop repeats the filter's (taps,
// jitter, clamping) so that the filter's own loop can gain options without touching this one.
// Run over the uniform tiles' list
// (TILE_LIST) or, without it, over the whole image. Compute only.
// NumPy twin: blurlab.twins.classify.uniform_gather.
#ifdef STAGE_COMPUTE
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D neighbor_max;
uniform int k;
uniform int samples;
uniform uint seed;

vec4 uniform_gather_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec2 vn = texelFetch(neighbor_max, x / k, 0).xy;
    float weight = 1.0 / len_half(vn);
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed) - 0.5;
    vec2 center = vec2(x) + 0.5;
    int skip = (samples % 2 == 1) ? (samples - 1) / 2 : -1;  // the center itself is X
    for (int i = 0; i < samples; ++i) {
        if (i == skip) continue;
        float t = -1.0 + 2.0 * (float(i) + j + 1.0) / float(samples + 1);
        ivec2 y = clamp(ivec2(floor(center + vn * t)), ivec2(0), size - 1);
        float dist = length(vec2(y - x));
        float c = cylinder(dist, vn);
        float a = 2.0 * cone(dist, vn) + 2.0 * c * c;
        weight += a;
        sum += a * sanitize_color(texelFetch(color, y, 0));
    }
    return sum / weight;
}
#endif

#define PASS_AT uniform_gather_at
#include "common/pass_main.glsl"
