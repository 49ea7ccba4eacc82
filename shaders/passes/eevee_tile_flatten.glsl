#version 450
// engine_eevee step 1, docs/spec.md §17.2: for each tile_size² tile, the longest prev half-motion
// E·M_prev (xy) and the longest E·M_next (zw) among its pixels, unclamped; the first in row-major order
// among equal lengths (the order-independent result of EEVEE's atomic max). Compute, two modes
// (uniform group_per_tile): one 16 x 16 work group per tile, each invocation scanning every 16th
// pixel of every 16th row, the picks merged in shared memory (common/tile_pick.glsl); or one
// invocation per tile scanning it all. Both give the same bits. NumPy twin:
// blurlab.twins.eevee.tile_flatten.
#include "common/eevee.glsl"
#include "common/tile_pick.glsl"

layout(binding = 0) uniform sampler2D motion_sides;  // RG: M_prev, BA: M_next (§17.1)
uniform int tile_size;
uniform float exposure;

layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

// Offers the pixels origin + first + step * (i, j) of `tile` inside the image, in row-major order.
void scan(ivec2 tile, ivec2 first, int step) {
    ivec2 origin = tile * tile_size;
    ivec2 end = min(origin + tile_size, textureSize(motion_sides, 0));
    for (int y = origin.y + first.y; y < end.y; y += step) {
        for (int x = origin.x + first.x; x < end.x; x += step) {
            vec4 m = texelFetch(motion_sides, ivec2(x, y), 0);
            vec2 p = scaled_motion(m.xy, exposure);
            vec2 n = scaled_motion(m.zw, exposure);
            int index = (y - origin.y) * tile_size + (x - origin.x);
            if (length(p) > picked_length.x) pick_prev(p, length(p), index);
            if (length(n) > picked_length.y) pick_next(n, length(n), index);
        }
    }
}

void store_pick(ivec2 tile, vec4 pick) {
    imageStore(tiles, tile, pick);
}

void main() {
    pick_tiles(imageSize(tiles));
}
