#version 450
// gather_gaussian (docs/spec.md §4): n taps at X - s·M, s = i/(n - 1) - 1/2, each weighted
// exp(-s² / 2σ²) with σ a fraction of the motion's length; the G-buffer at the shutter's
// center. Compute (default) or fragment. NumPy twin: twin.py, gather_gaussian.
#include "common/gather.glsl"

uniform int taps;
uniform float sigma;

vec4 gather_gaussian_at(ivec2 x) {
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy);
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {
        float s = float(i) / float(taps - 1) - 0.5;
        add_tap(center - s * m, exp(-s * s / (2.0 * sigma * sigma)), sum, total);
    }
    // If every tap fell outside under "ignore", keep the pixel.
    return total > 0.0 ? sum / total : sanitize_color(texelFetch(color, x, 0));
}

#define PASS_AT gather_gaussian_at
#include "common/pass_main.glsl"
