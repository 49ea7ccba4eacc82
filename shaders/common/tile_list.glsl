// Which pixel a compute invocation handles (include it in the STAGE_COMPUTE part of a pass).
// Without TILE_LIST: 16 x 16 threads per group over the whole image. With TILE_LIST (the
// pass runs over the tiles of one class of the tile classification, Jimenez 2014 —
// docs/classify_and_steps.md): 8 x 8 threads per group, work group (i, b) taking 8 x 8
// block b of the i-th listed tile; src/passes/classify_tiles.h writes the list and the
// indirect dispatch command. With TILE_LIST and WHOLE_TILES, work group i takes all of the
// i-th listed tile (listed_tile()), its 8 x 8 threads striding over it: for passes so cheap
// per pixel that the work groups' own cost would dominate (llvmpipe: tile_copy.glsl).
#ifdef TILE_LIST
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer TileList { uint listed_tiles[]; };
uniform int tile_list_k;  // tile side in pixels

ivec2 listed_tile() {
    uint entry = listed_tiles[gl_WorkGroupID.x];
    return ivec2(int(entry & 0xffffu), int(entry >> 16));
}

// Lanes past the tile's edge (k not a multiple of 8) get a pixel outside every image, which
// the pass's own bounds test drops.
const ivec2 OUTSIDE_THE_TILE = ivec2(1 << 30);

ivec2 invocation_pixel() {
    ivec2 tile = listed_tile();
    int blocks = (tile_list_k + 7) / 8;
    ivec2 block = ivec2(int(gl_WorkGroupID.y) % blocks, int(gl_WorkGroupID.y) / blocks);
    ivec2 inside = block * 8 + ivec2(gl_LocalInvocationID.xy);
    if (any(greaterThanEqual(inside, ivec2(tile_list_k)))) return OUTSIDE_THE_TILE;
    return tile * tile_list_k + inside;
}
#else
layout(local_size_x = 16, local_size_y = 16) in;

ivec2 invocation_pixel() {
    return ivec2(gl_GlobalInvocationID.xy);
}
#endif
