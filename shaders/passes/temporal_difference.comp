#version 450
// Temporal instability of one frame pair, docs/spec.md §21.3, summed per 16 x 16 tile: the sum over
// the tile's pixels and RGB of |(O_i − O_{i−1}) − (R_i − R_{i−1})|, each colour clipped to [0, 1]
// as the LDR metrics read it. The host adds the tiles in float64 and divides by 3·H·W.
// NumPy twin: blurlab.metrics.temporal.temporal_instability (one pair).
#include "common/inputs.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D output_now;
layout(binding = 1) uniform sampler2D output_before;
layout(binding = 2) uniform sampler2D reference_now;
layout(binding = 3) uniform sampler2D reference_before;
layout(binding = 0, r32f) uniform writeonly image2D tile_sums;

const int TILE = 16;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tile_sums)))) return;
    ivec2 first = tile * TILE;
    ivec2 last = min(first + TILE, textureSize(output_now, 0));
    float total = 0.0;
    for (int y = first.y; y < last.y; ++y) {
        for (int x = first.x; x < last.x; ++x) {
            ivec2 p = ivec2(x, y);
            vec3 change = (clipped_colour(output_now, p) - clipped_colour(output_before, p)) -
                          (clipped_colour(reference_now, p) - clipped_colour(reference_before, p));
            vec3 size = abs(change);
            total += size.r + size.g + size.b;
        }
    }
    imageStore(tile_sums, tile, vec4(total));
}
