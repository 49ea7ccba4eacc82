#version 450
// engine_eevee step 1, docs/spec.md §17.2: for each tile_size² tile, the longest prev half-motion
// E·M_prev (xy) and the longest E·M_next (zw) among its pixels, unclamped; the first in row-major order
// among equal lengths (the order-independent result of EEVEE's atomic max). Compute, one thread
// per tile. NumPy twin: blurlab.twins.eevee.tile_flatten.
#include "common/eevee.glsl"

layout(binding = 0) uniform sampler2D motion_sides;  // RG: M_prev, BA: M_next (§17.1)
uniform int tile_size;
uniform float exposure;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tiles)))) return;
    ivec2 origin = tile * tile_size;
    ivec2 end = min(origin + tile_size, textureSize(motion_sides, 0));
    vec4 best = vec4(0.0);
    vec2 best_length = vec2(-1.0);
    for (int y = origin.y; y < end.y; ++y) {
        for (int x = origin.x; x < end.x; ++x) {
            vec4 m = texelFetch(motion_sides, ivec2(x, y), 0);
            vec2 p = scaled_motion(m.xy, exposure);
            vec2 n = scaled_motion(m.zw, exposure);
            if (length(p) > best_length.x) {
                best.xy = p;
                best_length.x = length(p);
            }
            if (length(n) > best_length.y) {
                best.zw = n;
                best_length.y = length(n);
            }
        }
    }
    imageStore(tiles, tile, best);
}
