#version 450
// engine_unreal5 step 3a, docs/spec.md §17.7: the velocity dilation's scatter, where a tile's
// velocity reaches past the 7 x 7 tiles that step 3 gathers from. One work group per tile S of
// list LIST_FAR (common/tile_lists.glsl); for each velocity of S (the first, and with two
// directions the second) its threads walk the tiles D the velocity's segment may meet, column
// by column along its major axis, test each with the gather's own segment test (reaches_tile)
// and, for D outside S's 7 x 7, keep in far_key the largest far_key(v) (length code, then angle
// code) and in far_min the smallest tile minimum of S. Atomics make the result independent of
// the order in which tiles and threads run. NumPy twin: blurlab.twins.unreal5.far_tiles.
#define TILE_LISTS_READ 1
#define TILE_LIST_SAMPLER 1
#include "common/tile_lists.glsl"
#include "unreal5.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) uniform sampler2D tiles;
layout(binding = 0, r32ui) uniform uimage2D far_key_out;
layout(binding = 1, r32ui) uniform uimage2D far_min_out;
uniform float radius;  // R, pixels
uniform int directions;

void scatter(ivec2 source, vec2 codes, uint shortest, ivec2 grid) {
    vec2 v = decode_polar(codes, radius) / float(TILE);
    int major = abs(v.x) >= abs(v.y) ? 0 : 1;
    int minor = 1 - major;
    if (v[major] == 0.0) return;
    float widen = reach_widening(TILE);
    vec2 start = vec2(source) + 0.5 - v;
    vec2 d = 2.0 * v;
    // Candidate columns along the major axis, one tile of slack on either side.
    int first = max(int(floor(min(start[major], start[major] + d[major]) - widen)) - 1, 0);
    int last = min(int(floor(max(start[major], start[major] + d[major]) + widen)) + 1,
                   grid[major] - 1);
    for (int k = first + int(gl_LocalInvocationID.x); k <= last; k += 64) {
        float t1 = clamp((float(k) - widen - 1.0 - start[major]) / d[major], 0.0, 1.0);
        float t2 = clamp((float(k) + 2.0 + widen - start[major]) / d[major], 0.0, 1.0);
        float m1 = start[minor] + t1 * d[minor], m2 = start[minor] + t2 * d[minor];
        int low = max(int(floor(min(m1, m2) - widen)) - 1, 0);
        int high = min(int(floor(max(m1, m2) + widen)) + 1, grid[minor] - 1);
        for (int j = low; j <= high; ++j) {
            ivec2 target;
            target[major] = k;
            target[minor] = j;
            ivec2 offset = source - target;
            if (max(abs(offset.x), abs(offset.y)) <= NEIGHBORHOOD_REACH) continue;
            if (!reaches_tile(codes, offset, radius)) continue;
            imageAtomicMax(far_key_out, target, far_key(codes));
            imageAtomicMin(far_min_out, target, shortest);
        }
    }
}

void main() {
    ivec2 grid = textureSize(tiles, 0);
    ivec2 source = listed_tile(grid.x);
    vec4 s = texelFetch(tiles, source, 0);
    scatter(source, s.xy, uint(s.z), grid);
    if (directions == 2) scatter(source, unpack_codes(s.w), uint(s.z), grid);
}
