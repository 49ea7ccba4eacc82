// What engine_unreal5's passes share (docs/spec.md §17.7), beside engine_unreal's tile size,
// neighbourhood and skip threshold (common/unreal.glsl): the second direction, the tile classes
// (the order of the method's tile lists), the scatter beyond the neighbourhood and how many taps
// a line takes. NumPy twin: blurlab.twins.unreal5.
#include "common/polar_fixed_point.glsl"
#include "common/tile_reach.glsl"
#include "common/unreal.glsl"

const float AXIS_APART = 256.0;  // angle codes (45°): axes further apart are two directions
const float HALF_TURN = 1024.0;  // v and -v blur along the same axis
const float PACK = 2048.0;       // a second velocity travels as c_l·PACK + c_a
const float CLASS_SKIP = 0.0, CLASS_UNIFORM = 1.0, CLASS_GATHER = 2.0, CLASS_GATHER_2 = 3.0;
const float CLASS_UNIFORM_HALF = 4.0, CLASS_GATHER_HALF = 5.0;  // gathered at half resolution
const int LIST_FAR = 6;           // the list of tiles whose velocity reaches past the 7 x 7
const float SCATTER_BEYOND = 3.0;  // tiles of velocity from which a tile scatters (48 px)
const float PAIR_SPACING = 0.5;      // px of a line's longest half-vector per pair
const float HALF_RES_SPACING = 8.0;  // px between taps from which they read half_color

// Angle codes between the axes of two directions, 0..HALF_TURN/2.
float axis_gap(float a, float b) {
    float d = mod(abs(a - b), HALF_TURN);
    return min(d, HALF_TURN - d);
}

vec2 unpack_codes(float both) {
    return vec2(floor(both / PACK), mod(both, PACK));
}

// Pairs of taps on a line whose longest half-vector is `len` px, at most taps/2.
int line_pairs(float len, int taps) {
    return int(clamp(ceil(len / PAIR_SPACING), 1.0, float(taps / 2)));
}

// Whether such a line's taps lie HALF_RES_SPACING px apart or more and read half_color.
bool line_from_half(float len, int pairs, int half_res_gather) {
    return half_res_gather == 1 && len / float(pairs) >= HALF_RES_SPACING;
}

// A velocity as one uint that atomicMax orders by length code, then angle code.
uint far_key(vec2 codes) {
    return (uint(codes.x) << 11) | uint(codes.y);
}

vec2 far_codes(uint key) {
    return vec2(float(key >> 11), float(key & 2047u));
}
