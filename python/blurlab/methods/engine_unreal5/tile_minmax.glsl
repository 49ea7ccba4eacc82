#version 450
// engine_unreal5 step 2, docs/spec.md §17.7: per 16 x 16 tile engine_unreal's longest velocity
// (the first in row-major order among equal length codes) and smallest length code, and the
// longest velocity whose axis lies more than AXIS_APART angle codes from the first's (the first
// in row-major order among equal lengths; packed as c_l·PACK + c_a, 0: none). With SCATTER (the
// image's radius reaches past the 7 x 7 tiles), a tile whose velocity (either, with two
// directions) is SCATTER_BEYOND tiles long or longer joins list LIST_FAR
// (common/tile_lists.glsl), and the tile's scatter targets start empty: far_key 0, far_min all
// ones. Compute, one 16 x 16 work group per tile, one invocation per pixel: the extremes are
// atomic maxima and minima in shared memory of keys c_l·256 + (255 − the pixel's row-major index
// in the tile), exact integers, so they pick what a scan in row-major order picks.
// NumPy twin: blurlab.twins.unreal5.tile_minmax2 and far_tiles.
#include "unreal5.glsl"
#ifdef SCATTER
#define TILE_LISTS_APPEND 1
#include "common/tile_lists.glsl"
layout(binding = 3, r32ui) uniform writeonly uimage2D far_key_out;
layout(binding = 4, r32ui) uniform writeonly uimage2D far_min_out;
uniform float radius;  // R, pixels
uniform int directions;
#endif

layout(binding = 0) uniform sampler2D velocity;

layout(local_size_x = TILE, local_size_y = TILE) in;
layout(binding = 0, rgba32f) uniform writeonly image2D tiles;

shared uint longest_key, shortest_code, second_key;

// The pixel that `key` names in the tile at `origin`.
ivec2 keyed_pixel(uint key, ivec2 origin) {
    int index = 255 - int(key & 255u);
    return origin + ivec2(index % TILE, index / TILE);
}

void main() {
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 origin = tile * TILE;
    ivec2 x = origin + local;
    bool inside = all(lessThan(x, textureSize(velocity, 0)));
    uint order = 255u - uint(local.y * TILE + local.x);
    if (gl_LocalInvocationIndex == 0u) {
        longest_key = 0u;
        shortest_code = 0xffffffffu;
        second_key = 0u;
    }
    barrier();
    vec2 c = inside ? texelFetch(velocity, x, 0).xy : vec2(0.0);
    if (inside) {
        atomicMax(longest_key, (uint(c.x) << 8) | order);
        atomicMin(shortest_code, uint(c.x));
    }
    barrier();
    vec2 longest = texelFetch(velocity, keyed_pixel(longest_key, origin), 0).xy;
    if (inside && c.x > 0.0 && axis_gap(c.y, longest.y) > AXIS_APART)
        atomicMax(second_key, (uint(c.x) << 8) | order);
    barrier();
    if (gl_LocalInvocationIndex != 0u) return;
    vec2 second = second_key == 0u ? vec2(0.0)
                                   : texelFetch(velocity, keyed_pixel(second_key, origin), 0).xy;
    imageStore(tiles, tile, vec4(longest, float(shortest_code), second.x * PACK + second.y));
#ifdef SCATTER
    imageStore(far_key_out, tile, uvec4(0u));
    imageStore(far_min_out, tile, uvec4(0xffffffffu));
    float reach = max(longest.x, directions == 2 ? second.x : 0.0);
    if (reach / LENGTH_CODE_MAX * radius >= SCATTER_BEYOND * float(TILE))
        append_tile(LIST_FAR, tile, imageSize(tiles).x);
#endif
}
