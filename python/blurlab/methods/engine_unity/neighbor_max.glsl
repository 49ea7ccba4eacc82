#version 450
// engine_unity step 3, docs/spec.md §17.3: the longest coded velocity among the 3 x 3 tiles
// around each tile, the center's length counted 1.01 times (its key 1.0201 times), so that a
// neighbour must be clearly longer to win. Compute, one thread per tile.
// NumPy twin: twin.neighbor_max (twin.py).
#include "unity.glsl"

layout(binding = 0) uniform sampler2D tiles;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D neighbor_max;

const float CENTER_BIAS = 1.0201;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    vec2 best = texelFetch(tiles, tile, 0).xy;
    float best_key = CENTER_BIAS * code_key(best);
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = tile + ivec2(dx, dy);
            if ((dx == 0 && dy == 0) || any(lessThan(t, ivec2(0))) ||
                any(greaterThanEqual(t, grid)))
                continue;
            vec2 c = texelFetch(tiles, t, 0).xy;
            float k = code_key(c);
            if (k > best_key) {
                best = c;
                best_key = k;
            }
        }
    }
    imageStore(neighbor_max, tile, vec4(best, 0.0, 0.0));
}
