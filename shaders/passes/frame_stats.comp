#version 450
// Frame statistics, docs/spec.md §1.1: what the CPU needs to choose parameters, reduced per
// 16 x 16 tile so that only a few numbers per tile are read back instead of the image. One
// invocation per tile writes
//   tile_stats   (nearest, farthest) finite positive depth of the tile (+inf, -inf where none),
//                and the motion of its longest finite vector (its length is taken on the CPU with
//                np.hypot, as the NumPy path measures it);
//   tile_extent  the largest |component| of the tile's motion, +inf where any is not finite.
// NumPy twin: Frame.depth_range, Frame.longest_motion and Frame.layer_moves on arrays.
#include "common/inputs.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D depth;
layout(binding = 1) uniform sampler2D motion;
layout(binding = 0, rgba32f) uniform writeonly image2D tile_stats;
layout(binding = 1, r32f) uniform writeonly image2D tile_extent;

const int TILE = 16;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tile_stats)))) return;
    ivec2 size = textureSize(depth, 0);
    ivec2 first = tile * TILE;
    ivec2 last = min(first + TILE, size);
    float inf = uintBitsToFloat(0x7f800000u);
    float nearest = inf, farthest = -inf, extent = 0.0;
    vec2 longest = vec2(0.0);
    float longest_key = -1.0;
    for (int y = first.y; y < last.y; ++y) {
        for (int x = first.x; x < last.x; ++x) {
            float z = texelFetch(depth, ivec2(x, y), 0).x;
            if (is_finite_bits(z) && z > 0.0) {
                nearest = min(nearest, z);
                farthest = max(farthest, z);
            }
            vec2 m = texelFetch(motion, ivec2(x, y), 0).xy;
            if (!is_finite_bits(m.x) || !is_finite_bits(m.y)) {
                extent = inf;
                continue;
            }
            vec2 a = abs(m);
            extent = max(extent, max(a.x, a.y));
            // The length without overflow for any finite vector: the larger component times
            // the length of (1, smaller / larger).
            float big = max(a.x, a.y);
            float small = min(a.x, a.y);
            float ratio = big > 0.0 ? small / big : 0.0;
            float key = big * sqrt(1.0 + ratio * ratio);
            if (key > longest_key) {
                longest_key = key;
                longest = m;
            }
        }
    }
    imageStore(tile_stats, tile, vec4(nearest, farthest, longest));
    imageStore(tile_extent, tile, vec4(extent));
}
