#version 450
// engine_eevee step 2, docs/spec.md §17.2: each tile's motion dilated into the tiles it reaches.
// EEVEE scatters a conservative rasterization of each tile's motion line; this pass gathers the
// same result: each tile D looks at every tile S within reach and keeps, per side, the longest
// half-motion whose line (from S's center along -prev, or +next, clamped to max_blur, in tile
// units) meets D's square
// widened by h + REACH_MARGIN, h = 1/2 - 1/(2 tile_size); the first S in row-major order among
// equal lengths. Compute, two modes (uniform group_per_tile): one 16 x 16 work group per tile,
// each invocation looking at every 16th S of every 16th row of the reach, the picks merged in
// shared memory (common/tile_pick.glsl); or one invocation per tile looking at them all. Both
// give the same bits. NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/eevee.glsl"
#include "common/tile_reach.glsl"
#include "common/tile_pick.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform int tile_size;
uniform float max_blur;

layout(binding = 0, rgba32f) uniform writeonly image2D dilated;

// Offers the sources at offsets first + step * (i, j) from -radius to radius, in row-major order.
void scan(ivec2 tile, ivec2 first, int step) {
    ivec2 grid = textureSize(tiles, 0);
    int radius = min(int(ceil(max_blur / float(tile_size))) + 1, max(grid.x, grid.y));
    float widen = reach_widening(tile_size);
    for (int oy = -radius + first.y; oy <= radius; oy += step) {
        for (int ox = -radius + first.x; ox <= radius; ox += step) {
            ivec2 source = tile + ivec2(ox, oy);
            if (any(lessThan(source, ivec2(0))) || any(greaterThanEqual(source, grid))) continue;
            vec4 v = texelFetch(tiles, source, 0);
            vec2 start = vec2(ox, oy) + 0.5;  // S's center, in D's tile coordinates
            float lp = length(v.xy), ln = length(v.zw);
            int index = (oy + radius) * (2 * radius + 1) + (ox + radius);
            if (lp > picked_length.x &&
                segment_meets_box(start, -clamp_length(v.xy, max_blur) / float(tile_size), -widen,
                                  1.0 + widen)) {
                pick_prev(v.xy, lp, index);
            }
            if (ln > picked_length.y &&
                segment_meets_box(start, clamp_length(v.zw, max_blur) / float(tile_size), -widen,
                                  1.0 + widen)) {
                pick_next(v.zw, ln, index);
            }
        }
    }
}

void store_pick(ivec2 tile, vec4 pick) {
    imageStore(dilated, tile, pick);
}

void main() {
    pick_tiles(textureSize(tiles, 0));
}
