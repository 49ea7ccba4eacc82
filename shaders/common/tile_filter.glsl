// What the reconstruct passes of reconstruct_mcguire2012 and reconstruct_guertin2014 read
// (docs/spec.md §3): common/tile_filter_inputs.glsl, the NeighborMax grid (neighbor_max_of,
// tile_grid), and blurlab/methods/tile_filter.py's FILTER_OPTIONS under the same names (values
// validated in Python, once per call): uniforms, but for the options that pick the variant
// (VARIANT_OPTIONS: #defines).
#include "common/tile_filter_inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/filter_options.glsl"

// The options of common/filter_options.glsl that pick the pass's variant are #defines, 0 or 1
// (blurlab.methods.tile_filter.variant_defines), not uniforms: the jittered lookup's code, compiled
// in and switched off by a uniform, cost the H100 15 % of the reconstruct pass.
#if !defined(JITTER_TILES) || !defined(ADAPTIVE_SAMPLES)
#error "define JITTER_TILES and ADAPTIVE_SAMPLES (0 or 1): blurlab.methods.tile_filter.variant_defines"
#endif
const bool jitter_tiles = JITTER_TILES != 0;
const bool adaptive_samples = ADAPTIVE_SAMPLES != 0;
uniform float early_exit;  // pixels; 0: only the §3.4 test

#ifndef FUSED_NEIGHBOR_MAX
layout(binding = 3) uniform sampler2D neighbor_max;

ivec2 tile_grid() {
    return textureSize(neighbor_max, 0);
}

vec2 neighbor_max_of(ivec2 tile) {
    return texelFetch(neighbor_max, tile, 0).xy;
}
#else
// NeighborMax in the prologue (docs/spec.md §3.6), compute only and over the whole image: each
// 16 x 16 work group computes, from TileMax, the NeighborMax of every tile its pixels' lookups
// can reach into shared memory (the same function as passes/neighbor_max.glsl, so the same
// bits), and writes to the neighbor_max image the tiles whose first pixel is its own, so that
// each tile is written once.
#ifndef STAGE_COMPUTE
#error "FUSED_NEIGHBOR_MAX is for the compute backend over the whole image"
#endif
#include "common/neighbor_max.glsl"

layout(binding = 3) uniform sampler2D tile_max;
layout(binding = 1, rg32f) uniform writeonly image2D neighbor_max;
uniform bool diagonal_reach;

// A jittered lookup moves by at most k/4 px from a pixel's center, so a group's lookups reach
// (16 + 2 (k/4 + 2)) / k + 1 tiles per axis at most: 20 at k = 1, fewer for larger k.
const int GROUP_TILES_SIDE = 20;
const ivec2 GROUP_SIZE = ivec2(16);  // common/pass_main.glsl's, declared after this file
shared vec2 group_neighbor_max[GROUP_TILES_SIDE * GROUP_TILES_SIDE];
ivec2 group_first_tile;
ivec2 group_tiles;

ivec2 tile_grid() {
    return textureSize(tile_max, 0);
}

void neighbor_max_prologue() {
    ivec2 group = ivec2(gl_WorkGroupID.xy);
    ivec2 first_pixel = group * GROUP_SIZE;
    ivec2 last_pixel = min(first_pixel + GROUP_SIZE - 1, textureSize(color, 0) - 1);
    int reach = jitter_tiles ? k / 4 + 2 : 0;  // k/4 of jitter, half a pixel, rounded up
    group_first_tile = max(first_pixel - reach, ivec2(0)) / k;
    group_tiles = min((last_pixel + reach) / k, tile_grid() - 1) - group_first_tile + 1;
    group_tiles = min(group_tiles, ivec2(GROUP_TILES_SIDE));
    int count = group_tiles.x * group_tiles.y;
    for (int i = int(gl_LocalInvocationIndex); i < count; i += GROUP_SIZE.x * GROUP_SIZE.y) {
        ivec2 tile = group_first_tile + ivec2(i % group_tiles.x, i / group_tiles.x);
        vec2 v = neighbor_max_at(tile_max, tile, diagonal_reach);
        group_neighbor_max[i] = v;
        if (all(equal(tile * k / GROUP_SIZE, group))) imageStore(neighbor_max, tile, vec4(v, 0, 0));
    }
    barrier();
}

// Outside the group's tiles (which the bound above rules out) it is computed on the spot.
vec2 neighbor_max_of(ivec2 tile) {
    ivec2 i = tile - group_first_tile;
    if (any(lessThan(i, ivec2(0))) || any(greaterThanEqual(i, group_tiles))) {
        return neighbor_max_at(tile_max, tile, diagonal_reach);
    }
    return group_neighbor_max[i.y * group_tiles.x + i.x];
}
#define PASS_PROLOGUE neighbor_max_prologue
#endif
