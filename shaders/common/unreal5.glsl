// What engine_unreal5's passes share (docs/spec.md §17.7), beside engine_unreal's tile size,
// neighbourhood and skip threshold (common/unreal.glsl): the second direction and the classes.
// NumPy twin: blurlab.twins.unreal5.

const float AXIS_APART = 256.0;  // angle codes (45°): axes further apart are two directions
const float HALF_TURN = 1024.0;  // v and -v blur along the same axis
const float PACK = 2048.0;       // a second velocity travels as c_l·PACK + c_a
const float CLASS_SKIP = 0.0, CLASS_UNIFORM = 1.0, CLASS_GATHER = 2.0, CLASS_GATHER_2 = 3.0;

// Angle codes between the axes of two directions, 0..HALF_TURN/2.
float axis_gap(float a, float b) {
    float d = mod(abs(a - b), HALF_TURN);
    return min(d, HALF_TURN - d);
}

vec2 unpack_codes(float both) {
    return vec2(floor(both / PACK), mod(both, PACK));
}
