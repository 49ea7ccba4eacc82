#version 450
// engine_eevee step 2, docs/spec.md §17.2: each tile's motion dilated into the tiles it reaches.
// EEVEE scatters a conservative rasterization of each tile's motion line; this pass gathers the
// same result: each tile D looks at every tile S within reach and keeps, per side, the longest
// half-motion whose line (from S's center along -prev, or +next, clamped to max_blur, in tile
// units) meets D's square
// widened by h + REACH_MARGIN, h = 1/2 - 1/(2 tile_size). Compute, one thread per tile.
// NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/eevee.glsl"
#include "common/segment_box.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform int tile_size;
uniform float max_blur;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D dilated;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    int radius = min(int(ceil(max_blur / float(tile_size))) + 1, max(grid.x, grid.y));
    float widen = 0.5 - 0.5 / float(tile_size) + REACH_MARGIN;
    vec4 best = vec4(0.0);
    vec2 best_length = vec2(-1.0);
    for (int oy = -radius; oy <= radius; ++oy) {
        for (int ox = -radius; ox <= radius; ++ox) {
            ivec2 source = tile + ivec2(ox, oy);
            if (any(lessThan(source, ivec2(0))) || any(greaterThanEqual(source, grid))) continue;
            vec4 v = texelFetch(tiles, source, 0);
            vec2 start = vec2(ox, oy) + 0.5;  // S's center, in D's tile coordinates
            float lp = length(v.xy), ln = length(v.zw);
            if (lp > best_length.x &&
                segment_meets_box(start, -clamp_length(v.xy, max_blur) / float(tile_size), -widen,
                                  1.0 + widen)) {
                best.xy = v.xy;
                best_length.x = lp;
            }
            if (ln > best_length.y &&
                segment_meets_box(start, clamp_length(v.zw, max_blur) / float(tile_size), -widen,
                                  1.0 + widen)) {
                best.zw = v.zw;
                best_length.y = ln;
            }
        }
    }
    imageStore(dilated, tile, best);
}
