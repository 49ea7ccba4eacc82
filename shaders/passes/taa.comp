#version 450
// Temporal anti-aliasing, docs/spec.md §21.2, the form engines share:
//   h  = the history at X + 0.5 − V (bilinear, taps clamped to the image), V = the motion from
//        the previous frame to this one at X, in pixels; off screen outside [0, W] x [0, H];
//   h' = h held to the YCoCg box (per-channel min and max) of the current colour over the
//        neighbourhood ("3x3" or "cross"): "clip" moves h toward the box's centre until it is
//        inside, "clamp" clamps each channel, "none" keeps h;
//   n  = max(h.a, 0) + 1, w = max(blend, 1/n), out.rgb = h' + w·(c − h'), out.a = min(n, 1/blend);
//   no history (the first frame) or off screen: out.rgb = c, out.a = 1.
// NumPy twin: blurlab.twins.taa.resolve. Test: tests/test_taa.py.
#include "common/inputs.glsl"
#include "common/pixel.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D current;
layout(binding = 1) uniform sampler2D motion;   // pixels from the previous frame to this one
layout(binding = 2) uniform sampler2D history;  // the previous output (read only if has_history)
layout(binding = 0, rgba32f) uniform writeonly image2D resolved;
uniform float blend;
uniform int clip;
uniform int neighbourhood;
uniform int has_history;

const float CLIP_EPSILON = 1e-6;

vec3 ycocg(vec3 c) {
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
                -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}

vec3 rgb_from_ycocg(vec3 y) {
    return vec3(y.x + y.y - y.z, y.x + y.z, y.x - y.y - y.z);
}

vec3 current_ycocg(ivec2 p, ivec2 size) {
    return ycocg(sanitize_color(texelFetch(current, clamp_to_image(p, size), 0)).rgb);
}

vec4 history_at(ivec2 p, ivec2 size) {
    return sanitize_color(texelFetch(history, clamp_to_image(p, size), 0));
}

// Bilinear between texel centres, by hand: hardware filtering weighs with a few bits only.
vec4 bilinear_history(vec2 q, ivec2 size) {
    vec2 p = q - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    ivec2 i = ivec2(p0);
    vec4 top = mix(history_at(i, size), history_at(i + ivec2(1, 0), size), f.x);
    vec4 bottom = mix(history_at(i + ivec2(0, 1), size), history_at(i + ivec2(1, 1), size), f.x);
    return mix(top, bottom, f.y);
}

vec3 rectify(vec3 h, vec3 low, vec3 high) {
    if (clip == CLIP_CLAMP) return clamp(h, low, high);
    if (clip == CLIP_NONE) return h;
    vec3 centre = 0.5 * (low + high);
    vec3 extent = 0.5 * (high - low) + CLIP_EPSILON;
    vec3 offset = h - centre;
    vec3 units = abs(offset) / extent;
    float outside_by = max(units.x, max(units.y, units.z));
    return outside_by > 1.0 ? centre + offset / outside_by : h;
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(resolved);
    if (any(greaterThanEqual(x, size))) return;
    vec3 c = sanitize_color(texelFetch(current, x, 0)).rgb;
    vec2 q = vec2(x) + 0.5 - sanitize_motion(texelFetch(motion, x, 0).xy);
    bool on_screen = all(greaterThanEqual(q, vec2(0.0))) && all(lessThanEqual(q, vec2(size)));
    if (has_history == 0 || !on_screen) {
        imageStore(resolved, x, vec4(c, 1.0));
        return;
    }
    vec4 previous = bilinear_history(q, size);
    vec3 low = current_ycocg(x, size), high = low;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            if (neighbourhood == NEIGHBOURHOOD_CROSS && dx != 0 && dy != 0) continue;
            vec3 tap = current_ycocg(x + ivec2(dx, dy), size);
            low = min(low, tap);
            high = max(high, tap);
        }
    }
    vec3 held = rgb_from_ycocg(rectify(ycocg(previous.rgb), low, high));
    float count = max(previous.a, 0.0) + 1.0;
    float w = max(blend, 1.0 / count);
    imageStore(resolved, x, vec4(held + w * (c - held), min(count, 1.0 / blend)));
}
