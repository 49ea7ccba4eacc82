#version 450
// engine_eevee step 2, docs/spec.md §17.2: each tile's motion dilated into the tiles it reaches.
// EEVEE scatters a conservative rasterization of each tile's motion line; this pass gathers the
// same result: each tile D looks at every tile S within reach and keeps, per side, the longest
// half-motion whose line (from S's center along -prev, or +next, clamped to max_blur, in tile
// units) meets D's square widened by h + REACH_MARGIN + reach_jitter, h = 1/2 - 1/(2 tile_size)
// (reach_jitter 0 for engine_eevee, 1/4 for gather_coverage's jittered lookup, §17.6); the
// first S in row-major order among equal lengths (compared as common/tile_pick.glsl's pick_key
// says: exact for engine_eevee). Compute, two modes (#define GROUP_PER_TILE): a work group per
// tile whose invocations share the sources in reach, then merge their picks
// (common/tile_pick.glsl, layouts TILE_PICK_VARIANTS); or one invocation per tile looking at
// them all. All give the same bits. NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/tile_pick.glsl"
#include "common/eevee.glsl"
#include "common/tile_reach.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform int tile_size;
uniform float max_blur;
uniform float reach_jitter;  // tiles added to each reach

layout(binding = 0, rgba32f) uniform writeonly image2D dilated;

// How many tiles away a source can reach (the same for every tile).
int reach_radius() {
    ivec2 grid = textureSize(tiles, 0);
    return min(int(ceil(max_blur / float(tile_size))) + 1, max(grid.x, grid.y));
}

// The sources' offsets from -radius to radius on each axis, as a scan grid.
ivec2 tile_extent(ivec2 tile) {
    return ivec2(2 * reach_radius() + 1);
}

void consider(ivec2 tile, ivec2 p, uint index) {
    ivec2 offset = p - reach_radius();
    ivec2 source = tile + offset;
    if (any(lessThan(source, ivec2(0))) || any(greaterThanEqual(source, textureSize(tiles, 0)))) return;
    vec4 v = texelFetch(tiles, source, 0);
    vec2 start = vec2(offset) + 0.5;  // S's center, in D's tile coordinates
    float widen = reach_widening(tile_size) + reach_jitter;
    float lp = pick_key(length(v.xy)), ln = pick_key(length(v.zw));
    if (lp > picks[0].len &&
        segment_meets_box(start, -clamp_length(v.xy, max_blur) / float(tile_size), -widen, 1.0 + widen)) {
        offer(0, v.xy, lp, index);
    }
    if (ln > picks[1].len &&
        segment_meets_box(start, clamp_length(v.zw, max_blur) / float(tile_size), -widen, 1.0 + widen)) {
        offer(1, v.zw, ln, index);
    }
}

void store_pick(ivec2 tile, vec4 pick) {
    imageStore(dilated, tile, pick);
}

void main() {
    pick_tiles(textureSize(tiles, 0));
}
