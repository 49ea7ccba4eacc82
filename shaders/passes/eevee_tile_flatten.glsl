#version 450
// engine_eevee step 1, docs/spec.md §17.2: for each tile_size² tile, the longest prev half-motion
// E·M_prev (xy) and the longest E·M_next (zw) among its pixels, unclamped; the first in row-major order
// among equal lengths (the order-independent result of EEVEE's atomic max); lengths compared as
// common/tile_pick.glsl's pick_key says (exact for engine_eevee). Compute, two modes
// (#define GROUP_PER_TILE): a work group per tile whose invocations share its pixels, then
// merge their picks (common/tile_pick.glsl, layouts TILE_PICK_VARIANTS); or one invocation per
// tile scanning it all. All give the same bits. NumPy twin:
// blurlab.twins.eevee.tile_flatten.
#include "common/tile_pick.glsl"
#include "common/eevee.glsl"

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

void main() {
    pick_tiles(imageSize(tiles));
}
