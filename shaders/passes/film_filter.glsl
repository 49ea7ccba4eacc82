#version 450
// gather_coverage step 4 (docs/spec.md §17.6), when film_filter > 0: a Gaussian film filter of
// standard deviation film_filter px over the blurred image, out to ceil(3σ) px, coordinates
// clamped to the image, weights normalised over the whole kernel. It reconstructs a filtered
// pixel from pixel-centre samples, as a renderer's pixel filter does (Blender's EEVEE at its
// default 1.5 px filter size fits σ = 0.5, docs/engines.md). Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.film.film_filter.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
uniform float film_filter;  // σ, px

vec4 film_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    int r = int(ceil(3.0 * film_filter));
    float inv_two_var = 1.0 / (2.0 * film_filter * film_filter);
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
            float w = exp(-float(dx * dx + dy * dy) * inv_two_var);
            ivec2 y = clamp(x + ivec2(dx, dy), ivec2(0), size - 1);
            sum += w * sanitize_color(texelFetch(color, y, 0));
            total += w;
        }
    }
    return sum / total;
}

#define PASS_AT film_at
#include "common/pass_main.glsl"
