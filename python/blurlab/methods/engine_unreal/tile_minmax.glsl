#version 450
// engine_unreal step 2, docs/spec.md §17.5: per 16 x 16 tile (the last ones may be partial) the
// coded velocity of largest length code (the first in row-major order among equal codes) and
// the smallest length code. Compute, one thread per tile. NumPy twin: blurlab.twins.unreal.tile_minmax.
#include "common/unreal.glsl"

float block_key(vec2 code) { return code.x; }
#include "common/block_extremes.glsl"

layout(binding = 0) uniform sampler2D velocity;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tiles)))) return;
    BlockExtremes e = block_extremes(velocity, tile * TILE, TILE, vec2(-1.0, 0.0), -1.0);
    imageStore(tiles, tile, vec4(e.longest, e.shortest, 0.0));
}
