// NeighborMax of one tile, docs/spec.md §3.3: the TileMax of largest length among the 3 x 3 tiles
// around it, tiles outside the grid skipped, ties kept by the first in row order. With
// diagonal_reach (reconstruct_guertin2014, docs/guertin2014.md step 1), a diagonal tile counts
// only where its TileMax, extended both ways, can reach the center tile: both of its components
// point along the diagonal, (v.x dx)(v.y dy) > 0. Shared by passes/neighbor_max.glsl and the
// reconstruct passes that compute it in their prologue (common/tile_filter.glsl), so both give
// the same bits. Lengths compare as common/length_key.glsl says.
// NumPy twin: blurlab.twins.mcguire2012.neighbor_max.
#include "common/length_key.glsl"

vec2 neighbor_max_at(sampler2D tile_max, ivec2 tile, bool diagonal_reach) {
    ivec2 grid = textureSize(tile_max, 0);
    vec2 best = vec2(0.0);
    float best_length = -1.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = tile + ivec2(dx, dy);
            if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, grid))) continue;
            vec2 v = texelFetch(tile_max, t, 0).xy;
            if (diagonal_reach && dx != 0 && dy != 0 && (v.x * dx) * (v.y * dy) <= 0.0) continue;
            if (length_key(length(v)) > best_length) {
                best = v;
                best_length = length_key(length(v));
            }
        }
    }
    return best;
}
