#version 450
// Tile classes from motion (docs/spec.md §9.3): per tile of `tile` x `tile` pixels, the longest
// and shortest motion length |M| of its pixels; class 0 (still) where the longest is under
// `still_below` px, 1 (uniform) where the shortest is at least `uniform_ratio` times the longest,
// else 2 (mixed), as UE5's and HDRP's designs split their tiles. Writes each tile's class and
// appends the tile to its class's list (common/tile_lists.glsl). One invocation per tile.
// NumPy twin: blurlab.methods.tiles.motion_classes.
#define TILE_LISTS_APPEND 1
#include "common/inputs.glsl"
#include "common/tile_lists.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D motion;
layout(binding = 0, r32ui) uniform writeonly uimage2D tile_class;
uniform int tile;
uniform float still_below;
uniform float uniform_ratio;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = imageSize(tile_class);
    if (any(greaterThanEqual(t, grid))) return;
    ivec2 size = textureSize(motion, 0);
    ivec2 end = min(t * tile + tile, size);
    float longest = 0.0, shortest = uintBitsToFloat(0x7f800000u);
    for (int y = t.y * tile; y < end.y; ++y) {
        for (int x = t.x * tile; x < end.x; ++x) {
            float len = length(sanitize_motion(texelFetch(motion, ivec2(x, y), 0).xy));
            longest = max(longest, len);
            shortest = min(shortest, len);
        }
    }
    int cls = longest < still_below ? 0 : (shortest >= uniform_ratio * longest ? 1 : 2);
    imageStore(tile_class, t, uvec4(uint(cls)));
    append_tile(cls, t, grid.x);
}
