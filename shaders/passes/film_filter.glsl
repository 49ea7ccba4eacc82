#version 450
// gather_coverage step 4 (docs/spec.md §17.6), when film_filter > 0: a Gaussian film filter of
// standard deviation film_filter px over the blurred image, out to ceil(3σ) px, coordinates
// clamped to the image, weights normalised over the whole kernel. It reconstructs a filtered
// pixel from pixel-centre samples, as a renderer's pixel filter does (Blender's EEVEE at its
// default 1.5 px filter size fits σ = 0.5, docs/engines.md). Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.film.film_filter.
//
// Each 16 x 16 work group first loads its pixels and a border of ceil(3σ) px into shared
// memory, so a pixel reads its (2r + 1)² taps from there: 25 texture fetches per pixel cost
// 0.115 ms at 1080p on the H100 (RGBA32F). The taps are summed in the same order as before, so
// the bits are those of the fetching version.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
uniform float film_filter;  // σ, px: at most 4, the range methods/coverage.py declares

const int FILM_GROUP = 16;        // common/pass_main.glsl's work-group side
const int FILM_MAX_RADIUS = 12;   // ceil(3σ) at σ = 4, the largest the parameter allows
const int FILM_MAX_SPAN = FILM_GROUP + 2 * FILM_MAX_RADIUS;
shared vec4 film_tile[FILM_MAX_SPAN * FILM_MAX_SPAN];

int film_radius() {
    return min(int(ceil(3.0 * film_filter)), FILM_MAX_RADIUS);
}

// The group's pixels and their border, each coordinate clamped to the image as the taps are.
void film_prologue() {
    int r = film_radius();
    int span = FILM_GROUP + 2 * r;
    ivec2 size = textureSize(color, 0);
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * FILM_GROUP - r;
    for (int i = int(gl_LocalInvocationIndex); i < span * span; i += FILM_GROUP * FILM_GROUP) {
        ivec2 p = clamp(origin + ivec2(i % span, i / span), ivec2(0), size - 1);
        film_tile[i] = sanitize_color(texelFetch(color, p, 0));
    }
    barrier();
}

vec4 film_at(ivec2 x) {
    int r = film_radius();
    int span = FILM_GROUP + 2 * r;
    ivec2 center = ivec2(gl_LocalInvocationID.xy) + r;  // x's place in film_tile
    float inv_two_var = 1.0 / (2.0 * film_filter * film_filter);
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
            float w = exp(-float(dx * dx + dy * dy) * inv_two_var);
            sum += w * film_tile[(center.y + dy) * span + center.x + dx];
            total += w;
        }
    }
    return sum / total;
}

#define PASS_PROLOGUE film_prologue
#define PASS_AT film_at
#include "common/pass_main.glsl"
