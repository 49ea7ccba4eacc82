#version 450
// engine_hdrp steps 3 and 4, docs/spec.md §17.4: per tile D, the longest velocity among the 3 x 3
// tiles around it (scanned row by row, a candidate wins only if strictly longer) or, with
// `scatter`, among the tiles S within `radius` whose blur reaches D (the segment from S's center
// ± v/2, in tile units, meets D's square widened by h + REACH_MARGIN, h = 1/2 - 1/(2 tile)); the
// shortest length over the 3 x 3 tiles; and D's class: early-out (0) where the longest is under
// minimum_velocity, else fast (1) where the shortest is at least fast_ratio times the longest,
// else slow (2). D joins the tile list of its class (docs/spec.md §9.3,
// common/tile_lists.glsl). Compute, one thread per tile. NumPy twin: twin.py beside it.
// neighborhood, scatter_neighborhood, classify.
#define TILE_LISTS_APPEND 1
#include "common/tile_lists.glsl"
#include "common/small_float.glsl"
#include "common/polar_small_float.glsl"
#include "common/tile_reach.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform bool scatter;
uniform int radius;  // tiles scanned on each side with scatter
uniform int tile;    // px
uniform float minimum_velocity;
uniform float fast_ratio;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D neighborhood;

const float EARLY_OUT = 0.0, FAST = 1.0, SLOW = 2.0;

bool inside(ivec2 t, ivec2 grid) {
    return all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, grid));
}

void main() {
    ivec2 d = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (!inside(d, grid)) return;
    vec2 best = vec2(0.0, 0.5);
    float best_length = -1.0, shortest = 3.4e38;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = d + ivec2(dx, dy);
            if (!inside(t, grid)) continue;
            vec4 c = texelFetch(tiles, t, 0);
            shortest = min(shortest, c.z);
            if (!scatter && c.x > best_length) {
                best = c.xy;
                best_length = c.x;
            }
        }
    }
    if (scatter) {
        float widen = reach_widening(tile);
        for (int oy = -radius; oy <= radius; ++oy) {
            for (int ox = -radius; ox <= radius; ++ox) {
                ivec2 t = d + ivec2(ox, oy);
                if (!inside(t, grid)) continue;
                vec2 c = texelFetch(tiles, t, 0).xy;
                if (c.x <= best_length) continue;
                vec2 v = polar_decode(c) / float(tile);
                vec2 center = vec2(ox, oy) + 0.5;
                if (segment_meets_box(center - v * 0.5, v, -widen, 1.0 + widen)) {
                    best = c;
                    best_length = c.x;
                }
            }
        }
    }
    float longest = best.x;
    float c = shortest >= fast_ratio * longest ? FAST : SLOW;
    if (longest < minimum_velocity) c = EARLY_OUT;
    imageStore(neighborhood, d, vec4(best, shortest, c));
    append_tile(int(c), d, grid.x);
}
