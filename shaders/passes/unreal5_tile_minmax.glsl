#version 450
// engine_unreal5 step 2, docs/spec.md §17.7: per 16 x 16 tile engine_unreal's longest velocity
// and smallest length code (common/block_extremes.glsl), and the longest velocity whose axis
// lies more than AXIS_APART angle codes from the first's (the first in row-major order among
// equal lengths; packed as c_l·PACK + c_a, 0: none). With SCATTER (the image's radius reaches
// past the 7 x 7 tiles), a tile whose velocity (either, with two directions) is SCATTER_BEYOND
// tiles long or longer joins list LIST_FAR (common/tile_lists.glsl), and the tile's scatter
// targets start empty: far_key 0, far_min all ones. Compute, one thread per tile.
// NumPy twin: blurlab.twins.unreal5.tile_minmax2 and far_tiles.
#include "common/polar_fixed_point.glsl"
#include "common/unreal.glsl"
#include "common/unreal5.glsl"
#ifdef SCATTER
#define TILE_LISTS_APPEND 1
#include "common/tile_lists.glsl"
layout(binding = 3, r32ui) uniform writeonly uimage2D far_key_out;
layout(binding = 4, r32ui) uniform writeonly uimage2D far_min_out;
uniform float radius;  // R, pixels
uniform int directions;
#endif

float block_key(vec2 code) { return code.x; }
#include "common/block_extremes.glsl"

layout(binding = 0) uniform sampler2D velocity;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, imageSize(tiles)))) return;
    ivec2 origin = tile * TILE;
    BlockExtremes e = block_extremes(velocity, origin, TILE, vec2(-1.0, 0.0), -1.0);
    ivec2 end = min(origin + TILE, textureSize(velocity, 0));
    vec2 second = vec2(0.0);
    for (int y = origin.y; y < end.y; ++y) {
        for (int x = origin.x; x < end.x; ++x) {
            vec2 c = texelFetch(velocity, ivec2(x, y), 0).xy;
            if (axis_gap(c.y, e.longest.y) > AXIS_APART && c.x > second.x) second = c;
        }
    }
    imageStore(tiles, tile, vec4(e.longest, e.shortest, second.x * PACK + second.y));
#ifdef SCATTER
    imageStore(far_key_out, tile, uvec4(0u));
    imageStore(far_min_out, tile, uvec4(0xffffffffu));
    float longest = max(e.longest.x, directions == 2 ? second.x : 0.0);
    if (longest / LENGTH_CODE_MAX * radius >= SCATTER_BEYOND * float(TILE))
        append_tile(LIST_FAR, tile, imageSize(tiles).x);
#endif
}
