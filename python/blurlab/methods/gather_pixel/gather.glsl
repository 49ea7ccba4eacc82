#version 450
// gather_pixel, docs/spec.md §17.9: the tile-free gather of Bevy (0.14) and Unity URP along X's
// own motion. V = E·M(X)/2; n = min(ceil(|V|/spacing), samples) mirrored pairs at
// X ± (i + j)/n · V, j = rand(x, y, seed), taps clamped to the image; a tap weighs 1 at or
// behind X's depth and fades to 0 where it lies depth_extent in front of X; C(X) weighs 1 and
// the sum is normalised. Compute (default) or fragment.
// NumPy twin: twin.py, gather_pixel.
#include "common/gbuffer.glsl"
#include "common/random.glsl"

uniform int samples;
uniform float spacing;
uniform float depth_extent;
uniform float exposure;
uniform uint seed;

float front_weight(float z_x, float z_y) {
    float d = z_y == z_x ? 0.0 : (z_y - z_x) / depth_extent;
    return clamp(1.0 + d, 0.0, 1.0);
}

vec4 gather_pixel_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 sum = color_at(x);
    vec2 v = motion_at(x) * exposure * 0.5;
    int n = int(min(ceil(length(v) / spacing), float(samples)));
    if (n == 0) return sum;
    float z_x = depth_at(x);
    float j = rand(uint(x.x), uint(x.y), seed);
    vec2 center = vec2(x) + 0.5;
    float weight = 1.0;
    for (int i = 0; i < n; ++i) {
        vec2 offset = (float(i) + j) / float(n) * v;
        ivec2 y1 = clamp(ivec2(floor(center + offset)), ivec2(0), size - 1);
        ivec2 y2 = clamp(ivec2(floor(center - offset)), ivec2(0), size - 1);
        float a1 = front_weight(z_x, depth_at(y1));
        float a2 = front_weight(z_x, depth_at(y2));
        sum += a1 * color_at(y1) + a2 * color_at(y2);
        weight += a1 + a2;
    }
    return sum / weight;
}

#define PASS_AT gather_pixel_at
#include "common/pass_main.glsl"
