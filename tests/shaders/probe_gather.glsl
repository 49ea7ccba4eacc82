#version 450
// n equal taps backward (or centered) along the pixel's motion, over the gathers' shared taps
// (common/gather.glsl) and pass entry points (common/pass_main.glsl): a pass shaped as a
// method's, for tests/test_shader_pass.py (what reflect() lists, errors that name the shader).
#include "common/gather.glsl"

uniform int taps;
uniform float intensity;
uniform int direction;  // DIRECTION_BACKWARD or DIRECTION_CENTERED

vec4 probe_at(ivec2 x) {
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * intensity;
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {
        float s = float(i) / float(taps - 1) - (direction == DIRECTION_CENTERED ? 0.5 : 0.0);
        add_tap(center - s * m, 1.0, sum, total);
    }
    return total > 0.0 ? sum / total : sanitize_color(texelFetch(color, x, 0));
}

#define PASS_AT probe_at
#include "common/pass_main.glsl"
