// Tile lists and indirect dispatch (docs/spec.md §9.3; python/blurlab/methods/tiles.py): a
// classify pass appends each tile's index (row-major in the tile grid) to the list of its class,
// counting with an atomic counter per class; the counters are the work-group counts of an
// indirect dispatch (ShaderPass.run_indirect), so a later pass runs one work group per listed
// tile, and only over the tiles of its class.
//   tile_counts  R32UI, one row of 4 texels per class: (count, 1, 1, unused), the layout of
//                glDispatchComputeIndirect's three uints; the host sets (0, 1, 1, 0) first.
//   tile_lists   R32UI, one row per class, one texel per tile of the grid.
// A pass defines TILE_LISTS_APPEND (classify) or TILE_LISTS_READ (a pass over a list), and may
// define the units: TILE_COUNTS_UNIT, TILE_LISTS_UNIT (images) or TILE_LIST_SAMPLER (sampler).
#ifdef TILE_LISTS_APPEND
#ifndef TILE_COUNTS_UNIT
#define TILE_COUNTS_UNIT 1
#endif
#ifndef TILE_LISTS_UNIT
#define TILE_LISTS_UNIT 2
#endif
layout(binding = TILE_COUNTS_UNIT, r32ui) uniform uimage2D tile_counts;
layout(binding = TILE_LISTS_UNIT, r32ui) uniform writeonly uimage2D tile_lists;

// Appends tile `tile` of a grid `tiles_x` tiles wide to the list of class `cls`; the order
// within a list is whatever order the atomics ran in.
void append_tile(int cls, ivec2 tile, int tiles_x) {
    uint slot = imageAtomicAdd(tile_counts, ivec2(4 * cls, 0), 1u);
    imageStore(tile_lists, ivec2(int(slot), cls), uvec4(uint(tile.y * tiles_x + tile.x)));
}
#endif

#ifdef TILE_LISTS_READ
#ifndef TILE_LIST_SAMPLER
#define TILE_LIST_SAMPLER 7
#endif
layout(binding = TILE_LIST_SAMPLER) uniform usampler2D tile_lists;
uniform int tile_class;  // the list this dispatch runs over

// The tile this work group runs on: entry gl_WorkGroupID.x of list tile_class.
ivec2 listed_tile(int tiles_x) {
    int index = int(texelFetch(tile_lists, ivec2(int(gl_WorkGroupID.x), tile_class), 0).x);
    return ivec2(index % tiles_x, index / tiles_x);
}
#endif
