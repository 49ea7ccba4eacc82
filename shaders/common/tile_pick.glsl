// The choice both engine_eevee tile passes make (docs/spec.md §17.2 steps 1-2), per side (slot
// 0: prev, xy of the output; slot 1: next, zw): among the candidates a tile scans in row-major
// order, the longest (by pick_key), the first in that order among equal lengths, vec4(0) where
// there is none. pick_tiles() runs it in one of two modes (#define GROUP_PER_TILE): one invocation per tile
// scanning all its candidates, or a work group per tile whose invocations share them out, then
// merge their picks (common/group_pick.glsl: same bits either way). The group's layout is a
// variant (blurlab.methods.eevee.TILE_PICK_VARIANTS, timed by `blurlab bench layouts`
// --variants): by default 16 x 16 invocations each taking every 16th candidate of every 16th
// row; with TILE_PICK_THREADS N invocations in a row taking candidates t, t + N, ... in row
// order; TILE_PICK_SUBGROUP adds the subgroup reduction. The including pass defines consider()
// and tile_extent() (common/group_pick.glsl) and store_pick().
// NumPy twin: blurlab.twins.eevee.
#define PICK_SLOTS 2
#ifdef TILE_PICK_THREADS
#define PICK_ROWS TILE_PICK_THREADS
#else
#define PICK_GRID_SIDE 16
#endif
#ifdef TILE_PICK_SUBGROUP
#define PICK_SUBGROUP 1
#endif
#include "common/group_pick.glsl"

// What the including pass defines besides consider() and tile_extent(): where a pick goes.
void store_pick(ivec2 tile, vec4 pick);

uniform float length_steps;  // candidates compare floor(length · length_steps); 0: lengths

// The largest step key: 18 bits less one, so that key + 1 and a 14-bit tile index fit the
// 32-bit keys of the scatter dilation (common/reach_keys.glsl). 16384 px at 16 steps a px;
// longer lengths tie. twins.eevee.PICK_KEY_MAX.
const float PICK_KEY_MAX = 262142.0;

// What a candidate's length compares as: with length_steps > 0, lengths within the same
// 1/length_steps px step tie (and go to the first in row order), so that near-equal lengths,
// which float rounding orders differently on each device, pick alike.
float pick_key(float len) {
    return length_steps > 0.0 ? min(floor(len * length_steps), PICK_KEY_MAX) : len;
}

// The pass's main: picks for the tile this invocation (group) serves of a `grid`-sized output.
void pick_tiles(ivec2 grid) {
    ivec2 tile;
    if (pick_tile(grid, tile)) store_pick(tile, vec4(picks[0].v, picks[1].v));
}
