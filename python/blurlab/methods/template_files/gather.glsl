#version 450
// my_tent (spec.md beside this file); NumPy twin: twin.py. blurlab's common/inputs.glsl gives
// sanitize_color and sanitize_motion: how blurlab reads NaN and inf.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion;
uniform int taps;
uniform float scale;

vec4 my_tent_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * scale;
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {
        float s = (float(i) + 0.5) / float(taps) - 0.5;
        float weight = 1.0 - 2.0 * abs(s);
        ivec2 y = clamp(ivec2(floor(center - s * m)), ivec2(0), size - 1);
        sum += weight * sanitize_color(texelFetch(color, y, 0));
        total += weight;
    }
    return sum / total;
}

// The entry points: image `result`, one invocation per pixel.
#define PASS_AT my_tent_at
#include "common/pass_main.glsl"
