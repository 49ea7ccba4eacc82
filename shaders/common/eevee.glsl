// What engine_eevee's passes share (docs/spec.md §17.2): a pixel's half-motion as the filter
// reads it. NumPy twin: blurlab.twins.eevee.
#include "common/inputs.glsl"
#include "common/vector_clamps.glsl"

const float EARLY_EXIT = 0.5;      // px: a neighbourhood whose longest half-motion is shorter keeps C

// E·m (non-finite vectors are zero). Tiles are chosen by this length, before clamp_length:
// clamped lengths tie at max_blur, and float32 rounding would then pick among them at random.
vec2 scaled_motion(vec2 m, float exposure) {
    return sanitize_motion(m) * exposure;
}
