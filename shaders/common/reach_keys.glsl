// The 32-bit keys of the scatter dilation (docs/spec.md §17.6, "Steps 1–2 by scatter"): per
// destination tile and side, the largest (pick_key + 1) << 14 | (16383 − source index) that
// any source tile whose reach meets it offers, by imageAtomicMax. The larger key is the longer
// length, then the earlier source in row-major order: the gather dilation's pick. 0: none.
// Grids of more than 16384 tiles take the gather dilation (blurlab.methods.eevee). The keys
// image is (2·rows, columns): side 0 (prev) in rows 0..rows−1, side 1 (next) below.
// NumPy twin: blurlab.twins.eevee.tile_dilate (the same picks).
const uint REACH_INDEX_BITS = 14u;
const uint REACH_INDEX_MASK = (1u << REACH_INDEX_BITS) - 1u;

uint reach_key(float key, uint source_index) {
    return ((uint(key) + 1u) << REACH_INDEX_BITS) | (REACH_INDEX_MASK - source_index);
}

// The source tile a key names, in a grid `columns` wide; the key must not be 0.
ivec2 reach_source(uint key, int columns) {
    int index = int(REACH_INDEX_MASK - (key & REACH_INDEX_MASK));
    return ivec2(index % columns, index / columns);
}

// The dilated tile at `tile` (prev xy, next zw) that its keys name, from the flattened `tiles`
// (columns wide, rows high; the keys 2·rows high); 0 on a side without a key.
vec4 resolved_reach(usampler2D keys, sampler2D tiles, ivec2 tile) {
    ivec2 grid = textureSize(tiles, 0);
    uint prev_key = texelFetch(keys, tile, 0).x;
    uint next_key = texelFetch(keys, tile + ivec2(0, grid.y), 0).x;
    vec2 prev = prev_key == 0u ? vec2(0.0) : texelFetch(tiles, reach_source(prev_key, grid.x), 0).xy;
    vec2 next = next_key == 0u ? vec2(0.0) : texelFetch(tiles, reach_source(next_key, grid.x), 0).zw;
    return vec4(prev, next);
}
