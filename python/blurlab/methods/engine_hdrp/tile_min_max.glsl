#version 450
// engine_hdrp step 2, docs/spec.md §17.4: per tile of `tile` x `tile` pixels (the last row and
// column may be partial), the codes (length, turn) of its longest velocity, the first in
// row-major order among equal lengths, and its shortest length. Compute, one thread per tile.
// NumPy twin: twin.tile_min_max (twin.py).

float block_key(vec2 code) { return code.x; }
#include "common/block_extremes.glsl"

layout(binding = 0) uniform sampler2D velocity;
uniform int tile;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(tiles)))) return;
    BlockExtremes e = block_extremes(velocity, t * tile, tile, vec2(0.0, 0.5), -1.0);
    imageStore(tiles, t, vec4(e.longest, e.shortest, 0.0));
}
