// engine_eevee's dilation test (docs/spec.md §17.2 step 2) for common/tile_pick.glsl: the
// candidates of tile D are the tiles S within reach_radius() of it, and a side's half-motion of
// S is offered where its line (from S's center along -prev, or +next, clamped to reach_limit px,
// in tile units) meets D's square widened by h + REACH_MARGIN, h = 1/2 - 1/(2 tile_size). Shared
// by passes/eevee_tile_dilate.glsl (a pass of its own) and the prologue of
// passes/coverage_gather.glsl (common/coverage_dilation.glsl). The including pass declares
// sampler2D `tiles` (the flattened grid), int `tile_size` (px) and float `reach_limit` (px),
// includes common/tile_pick.glsl first, and defines source_motion() (below) after this file.
// NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/eevee.glsl"
#include "common/tile_reach.glsl"

// The including pass's: the flattened tile at `source` (inside the grid), read from `tiles` or
// from a copy of it.
vec4 source_motion(ivec2 source);

// How many tiles away a source can reach (the same for every tile).
int reach_radius() {
    ivec2 grid = textureSize(tiles, 0);
    return min(int(ceil(reach_limit / float(tile_size))) + 1, max(grid.x, grid.y));
}

// The sources' offsets from -radius to radius on each axis, as a scan grid.
ivec2 tile_extent(ivec2 tile) {
    return ivec2(2 * reach_radius() + 1);
}

void consider(ivec2 tile, ivec2 p, uint index) {
    ivec2 offset = p - reach_radius();
    ivec2 source = tile + offset;
    if (any(lessThan(source, ivec2(0))) || any(greaterThanEqual(source, textureSize(tiles, 0)))) return;
    vec4 v = source_motion(source);
    vec2 start = vec2(offset) + 0.5;  // S's center, in D's tile coordinates
    float widen = reach_widening(tile_size);
    float lp = pick_key(length(v.xy)), ln = pick_key(length(v.zw));
    if (lp > picks[0].len &&
        segment_meets_box(start, -clamp_length(v.xy, reach_limit) / float(tile_size), -widen, 1.0 + widen)) {
        offer(0, v.xy, lp, index);
    }
    if (ln > picks[1].len &&
        segment_meets_box(start, clamp_length(v.zw, reach_limit) / float(tile_size), -widen, 1.0 + widen)) {
        offer(1, v.zw, ln, index);
    }
}
