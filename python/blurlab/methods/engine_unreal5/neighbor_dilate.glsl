#version 450
// engine_unreal5 step 3, docs/spec.md §17.7: scatter-as-gather over the 7 x 7 tiles around each
// tile D, as engine_unreal's (§17.5 step 3), over each tile's first velocity and, with
// directions = 2, its second. D keeps the longest velocity that reaches it; with SCATTER, the
// scatter's far_key (tile_scatter.glsl) replaces it where longer, and its far_min joins
// the smallest minimum. With two directions D also keeps the longest reaching velocity of the
// 7 x 7 whose axis lies more than AXIS_APART from it. D's class: skip under SKIP_BELOW px;
// gather_2 where a second direction of SKIP_BELOW px or more reaches; uniform where
// min > 0.4·max (5·min > 2·max in codes), else gather; uniform and gather become uniform_half
// and gather_half where the first velocity's taps read half_color (line_from_half). D joins the
// list of its class (common/tile_lists.glsl). Compute, one thread per tile.
// NumPy twin: blurlab.twins.unreal5.neighbor_dilate2.
#define TILE_LISTS_APPEND 1
#include "common/tile_lists.glsl"
#include "unreal5.glsl"
#include "common/neighbor_dilate.glsl"

#ifdef SCATTER
layout(binding = 1) uniform usampler2D far_key_in;
layout(binding = 2) uniform usampler2D far_min_in;
#endif
uniform int directions;
uniform int taps;  // the quality level's sample count
uniform int half_res_gather;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    vec2 longest = vec2(-1.0, 0.0);
    vec2 second = vec2(0.0);
    float shortest = 1e30;
    for (int pass = 0; pass < directions; ++pass) {  // pass 1 needs pass 0's longest
        for (int oy = -NEIGHBORHOOD_REACH; oy <= NEIGHBORHOOD_REACH; ++oy) {
            for (int ox = -NEIGHBORHOOD_REACH; ox <= NEIGHBORHOOD_REACH; ++ox) {
                ivec2 source = tile + ivec2(ox, oy);
                if (outside(source, grid)) continue;
                vec4 s = texelFetch(tiles, source, 0);
                bool met = false;
                for (int k = 0; k < directions; ++k) {
                    vec2 c = k == 0 ? s.xy : unpack_codes(s.w);
                    if (!reaches_tile(c, ivec2(ox, oy), radius)) continue;
                    met = true;
                    if (pass == 0 && c.x > longest.x) longest = c;
                    if (pass == 1 && axis_gap(c.y, longest.y) > AXIS_APART && c.x > second.x)
                        second = c;
                }
                if (pass == 0 && met) shortest = min(shortest, s.z);
            }
        }
#ifdef SCATTER
        if (pass == 0) {
            uint key = texelFetch(far_key_in, tile, 0).x;
            if (key != 0u && far_codes(key).x > longest.x) longest = far_codes(key);
            uint far_min = texelFetch(far_min_in, tile, 0).x;
            if (far_min != 0xffffffffu) shortest = min(shortest, float(far_min));
        }
#endif
    }
    float kind = CLASS_GATHER;
    float len = longest.x / LENGTH_CODE_MAX * radius;
    if (len < SKIP_BELOW) kind = CLASS_SKIP;
    else if (second.x / LENGTH_CODE_MAX * radius >= SKIP_BELOW) kind = CLASS_GATHER_2;
    else if (5.0 * shortest > 2.0 * longest.x) kind = CLASS_UNIFORM;
    if ((kind == CLASS_UNIFORM || kind == CLASS_GATHER) &&
        line_from_half(len, line_pairs(len, taps), half_res_gather))
        kind += CLASS_UNIFORM_HALF - CLASS_UNIFORM;
    imageStore(neighbors, tile, vec4(longest, second.x * PACK + second.y, kind));
    append_tile(int(kind), tile, grid.x);
}
