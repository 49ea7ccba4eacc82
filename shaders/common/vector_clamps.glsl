// Length clamps of a motion vector (pixels). NumPy twins: blurlab.twins.eevee.clamp_length,
// blurlab.methods.engine_hdrp.twin.clamp_screen_fraction.

// v with its length clamped to max_len pixels (Blender's Max Blur, HDRP's Maximum Velocity).
vec2 clamp_length(vec2 v, float max_len) {
    float n = length(v);
    return n > max_len ? v * (max_len / n) : v;
}

// v with its length in screen units, (v.x/W, v.y/H), clamped to `fraction` (HDRP's camera
// clamps, "a fraction of the screen's full resolution"; docs/spec.md §17.4).
vec2 clamp_screen_fraction(vec2 v, float fraction, vec2 size) {
    float n = length(v / size);
    return n > fraction ? v * (fraction / n) : v;
}
