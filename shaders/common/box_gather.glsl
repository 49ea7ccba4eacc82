// The box gather of docs/spec.md §4 ("Blurry things"), shared by the method folders that gather
// along the G-buffer's motion and along the camera's alone: n equal taps at
// X - s·M·intensity, s = i/(n - 1) (backward, instant t1) or s = i/(n - 1) - 1/2 (centered,
// instant at the shutter's center). A pass defines PASS_AT box_gather_at. NumPy twin:
// blurlab.twins.gathers.box_gather.
#include "common/gather.glsl"

uniform int taps;
uniform float intensity;
uniform int direction;  // DIRECTION_BACKWARD or DIRECTION_CENTERED, as `edge` in gather.glsl

vec4 box_gather_at(ivec2 x) {
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * intensity;
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {
        float s = float(i) / float(taps - 1) - (direction == DIRECTION_CENTERED ? 0.5 : 0.0);
        add_tap(center - s * m, 1.0, sum, total);
    }
    // Backward: the first tap is X itself. Centered with an even n has no tap at X; if every
    // tap fell outside under "ignore", keep the pixel.
    return total > 0.0 ? sum / total : sanitize_color(texelFetch(color, x, 0));
}
