#version 450
// gather_weighted, docs/spec.md §4 (ogldev tutorial 41): m = M/2; taps at X, X - m, X - 2m, X - 3m
// with weights 0.4, 0.3, 0.2, 0.1. Instant t1. Compute (default) or fragment (the tutorial's).
// NumPy twin: twin.py, gather_weighted.
#include "common/gather.glsl"

vec4 gather_weighted_at(ivec2 x) {
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * 0.5;
    vec2 center = vec2(x) + 0.5;
    const float weights[4] = float[](0.4, 0.3, 0.2, 0.1);
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < 4; ++i) add_tap(center - float(i) * m, weights[i], sum, total);
    return sum / total;  // the center tap is always inside: total >= 0.4
}

#define PASS_AT gather_weighted_at
#include "common/pass_main.glsl"
