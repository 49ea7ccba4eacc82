#version 450
// engine_unreal step 2, docs/spec.md §17.5: per 16 x 16 tile (the last ones may be partial) the
// coded velocity of largest length code (the first in row-major order among equal codes) and
// the smallest length code. Compute, one thread per tile. NumPy twin: blurlab.twins.unreal.tile_minmax.
#include "common/unreal.glsl"

layout(binding = 0) uniform sampler2D velocity;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tiles)))) return;
    ivec2 origin = tile * TILE;
    ivec2 end = min(origin + TILE, textureSize(velocity, 0));
    vec2 longest = vec2(-1.0, 0.0);
    float shortest = 1e30;
    for (int y = origin.y; y < end.y; ++y) {
        for (int x = origin.x; x < end.x; ++x) {
            vec2 c = texelFetch(velocity, ivec2(x, y), 0).xy;
            if (c.x > longest.x) longest = c;
            shortest = min(shortest, c.x);
        }
    }
    imageStore(tiles, tile, vec4(longest, shortest, 0.0));
}
