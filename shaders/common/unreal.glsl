// What engine_unreal's passes share (docs/spec.md §17.5): the tile size, the neighbourhood's
// reach and its segment test, and the tile classes. NumPy twin: blurlab.twins.unreal.
#include "common/polar_fixed_point.glsl"
#include "common/tile_reach.glsl"

const int TILE = 16;                // tile side, pixels
const int NEIGHBORHOOD_REACH = 3;   // the 7 x 7 tiles around a tile
const float SKIP_BELOW = 0.5;       // px: a tile whose longest reaching velocity is shorter keeps C
const float TILE_SKIP = 0.0, TILE_FAST = 1.0, TILE_SLOW = 2.0;

// Whether velocity `codes` of the tile `offset` tiles from tile D (source minus D) reaches D:
// §17.5 step 3's segment test, the one engine_unreal's and engine_unreal5's 7 x 7 gathers and
// engine_unreal5's scatter all take.
bool reaches_tile(vec2 codes, ivec2 offset, float radius) {
    vec2 v = decode_polar(codes, radius) / float(TILE);
    vec2 center = vec2(offset) + 0.5;  // the source's center, in D's tile coordinates
    float widen = reach_widening(TILE);
    return segment_meets_box(center - v, 2.0 * v, -widen, 1.0 + widen);
}
