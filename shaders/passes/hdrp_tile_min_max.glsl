#version 450
// engine_hdrp step 2, docs/spec.md §17.4: per tile of `tile` x `tile` pixels (the last row and
// column may be partial), the codes (length, turn) of its longest velocity, the first in
// row-major order among equal lengths, and its shortest length. Compute, one thread per tile.
// NumPy twin: blurlab.twins.hdrp.tile_min_max.

layout(binding = 0) uniform sampler2D velocity;
uniform int tile;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(tiles)))) return;
    ivec2 origin = t * tile;
    ivec2 end = min(origin + tile, textureSize(velocity, 0));
    vec2 best = vec2(0.0, 0.5);
    float best_length = -1.0, shortest = 3.4e38;
    for (int y = origin.y; y < end.y; ++y) {
        for (int x = origin.x; x < end.x; ++x) {
            vec2 c = texelFetch(velocity, ivec2(x, y), 0).xy;
            if (c.x > best_length) {
                best = c;
                best_length = c.x;
            }
            shortest = min(shortest, c.x);
        }
    }
    imageStore(tiles, t, vec4(best, shortest, 0.0));
}
