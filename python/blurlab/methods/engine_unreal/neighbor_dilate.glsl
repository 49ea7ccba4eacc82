#version 450
// engine_unreal step 3, docs/spec.md §17.5: scatter-as-gather over the 7 x 7 tiles around each
// tile D. A tile S reaches D where the segment of its longest velocity through its center,
// from c_S - v_S to c_S + v_S in tile units, meets D's square widened as common/tile_reach.glsl
// says; D keeps the longest velocity of the tiles that reach it (the first in row-major order
// among equal codes) and their smallest length, and is classified: skip under SKIP_BELOW px,
// fast where min > 0.4·max (5·min > 2·max in codes), else slow. Compute, one thread per tile.
// NumPy twin: blurlab.twins.unreal.neighbor_dilate.
#include "common/neighbor_dilate.glsl"

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    vec2 longest = vec2(-1.0, 0.0);
    float shortest = 1e30;
    for (int oy = -NEIGHBORHOOD_REACH; oy <= NEIGHBORHOOD_REACH; ++oy) {
        for (int ox = -NEIGHBORHOOD_REACH; ox <= NEIGHBORHOOD_REACH; ++ox) {
            ivec2 source = tile + ivec2(ox, oy);
            if (outside(source, grid)) continue;
            vec4 s = texelFetch(tiles, source, 0);
            if (!reaches_tile(s.xy, ivec2(ox, oy), radius)) continue;
            if (s.x > longest.x) longest = s.xy;
            shortest = min(shortest, s.z);
        }
    }
    float kind = TILE_SLOW;
    if (longest.x / LENGTH_CODE_MAX * radius < SKIP_BELOW) kind = TILE_SKIP;
    else if (5.0 * shortest > 2.0 * longest.x) kind = TILE_FAST;
    imageStore(neighbors, tile, vec4(longest, shortest, kind));
}
