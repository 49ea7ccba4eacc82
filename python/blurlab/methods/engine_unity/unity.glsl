// What engine_unity's passes share (docs/spec.md §17.3): velocities as 10-bit codes c in
// 0..1023, v = (2c/1023 - 1)·R, and the exact integer key by which tiles compare them.
// NumPy twin: twin.py beside it.

const float CODE_MAX = 1023.0;

// Squared length in units of (R/1023)²: an integer below 2^22, exact in float32.
float code_key(vec2 c) {
    vec2 d = 2.0 * c - CODE_MAX;
    return d.x * d.x + d.y * d.y;
}

vec2 decode_velocity(vec2 c, float radius) {
    return (2.0 * c / CODE_MAX - 1.0) * radius;
}
