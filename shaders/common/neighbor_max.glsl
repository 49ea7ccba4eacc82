// NeighborMax of one tile, docs/spec.md §3.3: the TileMax of largest length among the 3 x 3 tiles
// around it, tiles outside the grid skipped, ties kept by the first in row order. With
// diagonal_reach (reconstruct_guertin2014, docs/guertin2014.md step 1), a diagonal tile counts
// only where its TileMax, extended both ways, can reach the center tile: both of its components
// point along the diagonal, (v.x dx)(v.y dy) > 0. Shared by passes/neighbor_max.glsl and the
// reconstruct passes that compute it themselves (common/tile_filter.glsl, common/tile_chain.glsl),
// so all give the same bits. NumPy twin: blurlab.twins.mcguire2012.neighbor_max.

// Offers the TileMax v of the tile at offset d from the center to the running choice (best,
// best_length): kept where it counts (diagonal_reach) and is longer. The loop over the 3 x 3 that
// calls it reads TileMax from a sampler here, from an image in common/tile_chain.glsl.
void offer_neighbor(vec2 v, ivec2 d, bool diagonal_reach, inout vec2 best, inout float best_length) {
    if (diagonal_reach && d.x != 0 && d.y != 0 && (v.x * d.x) * (v.y * d.y) <= 0.0) return;
    if (length(v) > best_length) {
        best = v;
        best_length = length(v);
    }
}

vec2 neighbor_max_at(sampler2D tile_max, ivec2 tile, bool diagonal_reach) {
    ivec2 grid = textureSize(tile_max, 0);
    vec2 best = vec2(0.0);
    float best_length = -1.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = tile + ivec2(dx, dy);
            if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, grid))) continue;
            offer_neighbor(texelFetch(tile_max, t, 0).xy, ivec2(dx, dy), diagonal_reach, best, best_length);
        }
    }
    return best;
}
