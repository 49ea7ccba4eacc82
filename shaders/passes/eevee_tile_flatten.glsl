#version 450
// engine_eevee step 1, docs/spec.md §17.2: for each tile_size² tile, the longest prev half-motion
// E·M_prev (xy) and the longest E·M_next (zw) among its pixels, unclamped; the first in row-major order
// among equal lengths (the order-independent result of EEVEE's atomic max); lengths compared as
// common/tile_pick.glsl's pick_key says (exact for engine_eevee). Compute, two modes
// (#define GROUP_PER_TILE): a work group per tile whose invocations share its pixels, then
// merge their picks (common/tile_pick.glsl, layouts TILE_PICK_VARIANTS); or one invocation per
// tile scanning it all. All give the same bits. With SCATTER_DILATION (gather_coverage's scatter
// dilation, docs/spec.md §17.6) the tile then offers its picks to every tile its reach meets,
// by atomic max on reach_keys (common/reach_keys.glsl), shared out among the group's
// invocations; passes/eevee_tile_resolve.glsl turns the keys into the dilated tiles.
// NumPy twin: blurlab.twins.eevee.tile_flatten (and tile_dilate).
#include "common/tile_pick.glsl"
#include "common/eevee.glsl"
#ifdef SCATTER_DILATION
#include "common/tile_reach.glsl"
#include "common/reach_keys.glsl"
#endif

layout(binding = 0) uniform sampler2D motion_sides;  // RG: M_prev, BA: M_next (§17.1)
uniform int tile_size;
uniform float exposure;

layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

// The tile's pixels inside the image.
ivec2 tile_extent(ivec2 tile) {
    return min(tile * tile_size + tile_size, textureSize(motion_sides, 0)) - tile * tile_size;
}

void consider(ivec2 tile, ivec2 p, uint index) {
    vec4 m = texelFetch(motion_sides, tile * tile_size + p, 0);
    vec2 prev = scaled_motion(m.xy, exposure);
    vec2 next = scaled_motion(m.zw, exposure);
    offer(0, prev, pick_key(length(prev)), index);
    offer(1, next, pick_key(length(next)), index);
}

void store_pick(ivec2 tile, vec4 pick) {
    imageStore(tiles, tile, pick);
}

#ifdef SCATTER_DILATION
uniform float max_blur;
uniform float reach_jitter;  // tiles added to each reach (gather_coverage's jittered lookup)
layout(binding = 1, r32ui) uniform uimage2D reach_keys;

// Offers `tile`'s picks to the tiles its prev and next reach meet (§17.2 step 2's test, on the
// same floats as passes/eevee_tile_dilate.glsl): the candidates in the reach's bounding box,
// one more tile each way against rounding, within the dilation's radius; invocation `lane` of
// `lanes` takes every lanes-th of them.
void scatter_reach(ivec2 tile, ivec2 grid, int lane, int lanes) {
    int radius = min(int(ceil(max_blur / float(tile_size))) + 1, max(grid.x, grid.y));
    float widen = reach_widening(tile_size) + reach_jitter;
    uint index = uint(tile.y * grid.x + tile.x);
    for (int side = 0; side < 2; ++side) {
        vec2 line = (side == 0 ? -1.0 : 1.0) * clamp_length(picks[side].v, max_blur) / float(tile_size);
        uint key = reach_key(picks[side].len, index);
        vec2 start = vec2(tile) + 0.5, end = start + line;
        ivec2 low = max(ivec2(floor(min(start, end) - widen)) - 2, max(tile - radius, ivec2(0)));
        ivec2 high = min(ivec2(floor(max(start, end) + widen)) + 1, min(tile + radius, grid - 1));
        ivec2 extent = max(high - low + 1, ivec2(0));
        for (int i = lane; i < extent.x * extent.y; i += lanes) {
            ivec2 target = low + ivec2(i % extent.x, i / extent.x);
            if (segment_meets_box(vec2(tile - target) + 0.5, line, -widen, 1.0 + widen)) {
                imageAtomicMax(reach_keys, target + ivec2(0, side * grid.y), key);
            }
        }
    }
}
#endif

void main() {
#ifdef SCATTER_DILATION
    ivec2 grid = imageSize(tiles);
    ivec2 tile;
    bool holds = pick_tile(grid, tile);
    if (holds) store_pick(tile, vec4(picks[0].v, picks[1].v));
    // With a group per tile every invocation holds the group's picks after the merge.
    if (group_per_tile) {
        scatter_reach(tile, grid, int(gl_LocalInvocationIndex), PICK_GROUP_SIZE);
    } else if (holds) {
        scatter_reach(tile, grid, 0, 1);
    }
#else
    pick_tiles(imageSize(tiles));
#endif
}
