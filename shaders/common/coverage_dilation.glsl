// gather_coverage's tile dilation (docs/spec.md §17.6 step 2) in its gather's prologue, layout
// GATHER_FUSED_DILATION (blurlab.methods.coverage.GATHER_VARIANTS): instead of a pass of its own
// (passes/eevee_tile_dilate.glsl), each 16 x 16 work group first dilates every tile its pixels'
// jittered lookups can reach, into shared memory, with the same test (common/tile_dilate.glsl)
// and the same pick (common/tile_pick.glsl): the same bits. Each tile takes a run of the
// group's invocations (the runs as long as the tiles allow, a power of two), which share its
// sources in row order and merge their picks (reduce_picks_in); with GATHER_DILATION_CACHE the
// sources come from a copy in shared memory (below). The group also writes, to image
// `dilated`, the tiles whose first pixel is its own, so each tile of the grid is written once
// and the method still returns the dilated grid. Included by passes/coverage_gather.glsl after
// its uniforms tile_size and reach_limit; defines dilated_grid() and dilated_motion(tile).
// NumPy twin: blurlab.twins.eevee.tile_dilate.
#ifndef STAGE_COMPUTE
#error "GATHER_FUSED_DILATION needs the compute backend (a work group's shared memory)"
#endif
#ifdef FILM_IN_PASS
#error "GATHER_FUSED_DILATION dilates a 16 x 16 group's tiles; an in_gather film block is not one"
#endif
#ifdef TILE_PICK_SUBGROUP
#error "GATHER_FUSED_DILATION merges several tiles' picks per group: no subgroup reduction"
#endif
#include "common/tile_pick.glsl"

layout(binding = 3) uniform sampler2D tiles;  // the flattened grid (§17.2 step 1)
layout(binding = 1, rgba32f) uniform writeonly image2D dilated;

#include "common/tile_dilate.glsl"

const ivec2 GROUP_SIZE = ivec2(16);  // common/pass_main.glsl's work group
// A jittered lookup lands within tile_size / 4 px of a pixel's center, so a group's lookups
// fall within (tile_size + 3) / 4 + 1 px of its pixels: 16 + 2 (tile_size + 3) / 4 + 2 px,
// which spans at most 4 tiles per axis for tiles of 8 px or more (gather_coverage's smallest;
// tests/test_gather_coverage.py checks the bound).
const int GROUP_TILES_SIDE = 4;
shared vec4 group_dilated[GROUP_TILES_SIDE * GROUP_TILES_SIDE];
ivec2 group_first_tile;
ivec2 group_tiles;

int lookup_reach() {
    return (tile_size + 3) / 4 + 1;
}

#ifdef GATHER_DILATION_CACHE
// Layout fused_dilation_cached: the group's tiles share most of their sources (at 1080p 4
// tiles scan 4 x 625 of them, 676 distinct), so the group first copies them into shared memory
// where they fit, CACHE_TILES of them (16 KiB: with the picks' 8 KiB under llvmpipe's 32 KiB),
// 2 radius + 4 tiles per axis at most; where they do not (a long reach over small tiles),
// each read goes to `tiles`. The same values either way: the same bits.
const int CACHE_TILES = 1024;
shared vec4 cached_sources[CACHE_TILES];
ivec2 cache_first;
ivec2 cache_size;
bool cached;

void cache_sources(ivec2 last_tile) {
    ivec2 grid = textureSize(tiles, 0);
    cache_first = max(group_first_tile - reach_radius(), ivec2(0));
    cache_size = min(last_tile + reach_radius(), grid - 1) - cache_first + 1;
    int count = cache_size.x * cache_size.y;
    cached = count <= CACHE_TILES;
    if (cached) {
        for (int k = int(gl_LocalInvocationIndex); k < count; k += PICK_GROUP_SIZE) {
            cached_sources[k] = texelFetch(tiles, cache_first + ivec2(k % cache_size.x, k / cache_size.x), 0);
        }
    }
    barrier();
}

vec4 source_motion(ivec2 source) {
    if (!cached) return texelFetch(tiles, source, 0);
    ivec2 i = source - cache_first;
    return cached_sources[i.y * cache_size.x + i.x];
}
#else
vec4 source_motion(ivec2 source) {
    return texelFetch(tiles, source, 0);
}
#endif

void store_pick(ivec2 tile, vec4 pick) {
    ivec2 i = tile - group_first_tile;
    group_dilated[i.y * group_tiles.x + i.x] = pick;
    if (all(equal(tile * tile_size / GROUP_SIZE, ivec2(gl_WorkGroupID.xy)))) imageStore(dilated, tile, pick);
}

void dilation_prologue() {
    ivec2 first_pixel = ivec2(gl_WorkGroupID.xy) * GROUP_SIZE;
    ivec2 last_pixel = min(first_pixel + GROUP_SIZE - 1, textureSize(color, 0) - 1);
    ivec2 grid = textureSize(tiles, 0);
    group_first_tile = max(first_pixel - lookup_reach(), ivec2(0)) / tile_size;
    ivec2 last_tile = min((last_pixel + lookup_reach()) / tile_size, grid - 1);
    group_tiles = min(last_tile - group_first_tile + 1, ivec2(GROUP_TILES_SIDE));
#ifdef GATHER_DILATION_CACHE
    cache_sources(group_first_tile + group_tiles - 1);
#endif
    int count = group_tiles.x * group_tiles.y;
    uint lanes = uint(PICK_GROUP_SIZE);
    while (lanes * uint(count) > uint(PICK_GROUP_SIZE)) lanes /= 2u;
    uint i = gl_LocalInvocationIndex;
    int run = int(i / lanes);
    ivec2 tile = group_first_tile + ivec2(run % group_tiles.x, run / group_tiles.x);
    clear_picks();
    if (run < count) scan_rows(tile, tile_extent(tile), int(i % lanes), int(lanes));
    reduce_picks_in(lanes);
    if (run < count && i % lanes == 0u) store_pick(tile, vec4(picks[0].v, picks[1].v));
    barrier();
}

ivec2 dilated_grid() {
    return textureSize(tiles, 0);
}

// A tile the group's pixels look up (dilation_prologue has dilated it).
vec4 dilated_motion(ivec2 tile) {
    ivec2 i = tile - group_first_tile;
    return group_dilated[i.y * group_tiles.x + i.x];
}

#define PASS_PROLOGUE dilation_prologue
