#version 450
// engine_unreal5 step 3, docs/spec.md §17.7: scatter-as-gather over the 7 x 7 tiles around each
// tile D, as engine_unreal's (§17.5 step 3), over each tile's first velocity and, with
// directions = 2, its second. D keeps the longest velocity that reaches it, with two directions
// the longest reaching one whose axis lies more than AXIS_APART from it, and its class: skip
// under SKIP_BELOW px; gather_2 where a second direction of SKIP_BELOW px or more reaches;
// uniform where min > 0.4·max (5·min > 2·max in codes); else gather. Compute, one thread per
// tile. NumPy twin: blurlab.twins.unreal5.neighbor_dilate2.
#include "common/polar_fixed_point.glsl"
#include "common/tile_reach.glsl"
#include "common/unreal.glsl"
#include "common/unreal5.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform float radius;  // R, pixels
uniform int directions;

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D neighbors;

bool reaches_tile(vec2 codes, ivec2 offset, float widen) {
    vec2 v = decode_polar(codes, radius) / float(TILE);
    vec2 center = vec2(offset) + 0.5;  // the source's center, in D's tile coordinates
    return segment_meets_box(center - v, 2.0 * v, -widen, 1.0 + widen);
}

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    float widen = reach_widening(TILE);
    vec2 longest = vec2(-1.0, 0.0);
    vec2 second = vec2(0.0);
    float shortest = 1e30;
    for (int pass = 0; pass < directions; ++pass) {  // pass 1 needs pass 0's longest
        for (int oy = -NEIGHBORHOOD_REACH; oy <= NEIGHBORHOOD_REACH; ++oy) {
            for (int ox = -NEIGHBORHOOD_REACH; ox <= NEIGHBORHOOD_REACH; ++ox) {
                ivec2 source = tile + ivec2(ox, oy);
                if (any(lessThan(source, ivec2(0))) || any(greaterThanEqual(source, grid))) continue;
                vec4 s = texelFetch(tiles, source, 0);
                bool met = false;
                for (int k = 0; k < directions; ++k) {
                    vec2 c = k == 0 ? s.xy : unpack_codes(s.w);
                    if (!reaches_tile(c, ivec2(ox, oy), widen)) continue;
                    met = true;
                    if (pass == 0 && c.x > longest.x) longest = c;
                    if (pass == 1 && axis_gap(c.y, longest.y) > AXIS_APART && c.x > second.x)
                        second = c;
                }
                if (pass == 0 && met) shortest = min(shortest, s.z);
            }
        }
    }
    float kind = CLASS_GATHER;
    if (longest.x / LENGTH_CODE_MAX * radius < SKIP_BELOW) kind = CLASS_SKIP;
    else if (second.x / LENGTH_CODE_MAX * radius >= SKIP_BELOW) kind = CLASS_GATHER_2;
    else if (5.0 * shortest > 2.0 * longest.x) kind = CLASS_UNIFORM;
    imageStore(neighbors, tile, vec4(longest, second.x * PACK + second.y, kind));
}
