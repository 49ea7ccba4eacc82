#version 450
// gather_coverage step 4 (docs/spec.md §17.6), when film_filter > 0: a Gaussian film filter of
// standard deviation film_filter px over the blurred image, out to FILM_RADIUS = ceil(3σ) px (a
// #define the method sets, so that the loops unroll), coordinates clamped to the image, weights
// normalised over the whole kernel. It reconstructs a filtered pixel from pixel-centre samples,
// as a renderer's pixel filter does (Blender's EEVEE at its default 1.5 px filter size fits
// σ = 0.5, docs/engines.md). The Gaussian and the clamping are separable, so the 2D weight of
// (dx, dy) is w(dx)·w(dy) of the normalised 1D kernel w, whose FILM_RADIUS + 1 values each
// invocation computes once. Three variants (blurlab.methods.coverage.FILM_VARIANTS): by default
// one pass over the (2R + 1)² taps; with FILM_SEPARABLE two passes of 2R + 1 taps, along rows
// (film_columns false) then along columns of the rows' result; with FILM_SHARED one pass whose
// work group first filters along rows its 16 x (16 + 2R) pixels into shared memory, then each
// invocation along its column there (the rows of the apron filtered twice, by the groups
// above and below: (16 + 2R)/16 row taps a pixel). Compute, one invocation per pixel.
// NumPy twin: blurlab.twins.film.film_filter.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
uniform float film_filter;  // σ, px
#ifdef FILM_SEPARABLE
uniform bool film_columns;  // this pass filters along columns; else along rows
#endif

// The normalised 1D kernel at distances 0 .. FILM_RADIUS.
float[FILM_RADIUS + 1] film_weights() {
    float weights[FILM_RADIUS + 1];
    float inv_two_var = 1.0 / (2.0 * film_filter * film_filter);
    float total = 0.0;
    for (int d = 0; d <= FILM_RADIUS; ++d) {
        weights[d] = exp(-float(d * d) * inv_two_var);
        total += d == 0 ? weights[d] : 2.0 * weights[d];
    }
    for (int d = 0; d <= FILM_RADIUS; ++d) weights[d] /= total;
    return weights;
}

#ifdef FILM_SHARED
// The work group's 16 columns filtered along rows, on its 16 rows and FILM_RADIUS rows above
// and below (clamped to the image), for the columns pass to read.
const int FILM_GROUP = 16;  // common/pass_main.glsl's work group side
shared vec4 film_rows[FILM_GROUP + 2 * FILM_RADIUS][FILM_GROUP];

void film_rows_prologue() {
    ivec2 last = textureSize(color, 0) - 1;
    float weights[FILM_RADIUS + 1] = film_weights();
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * FILM_GROUP;
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    int x = origin.x + local.x;  // may lie beyond the image: its column is never stored
    for (int r = local.y; r < FILM_GROUP + 2 * FILM_RADIUS; r += FILM_GROUP) {
        int y = clamp(origin.y - FILM_RADIUS + r, 0, last.y);
        vec4 sum = vec4(0.0);
        for (int d = -FILM_RADIUS; d <= FILM_RADIUS; ++d) {
            sum += weights[abs(d)] * sanitize_color(texelFetch(color, ivec2(clamp(x + d, 0, last.x), y), 0));
        }
        film_rows[r][local.x] = sum;
    }
    barrier();
}
#define PASS_PROLOGUE film_rows_prologue
#endif

vec4 film_at(ivec2 x) {
    ivec2 last = textureSize(color, 0) - 1;
    float weights[FILM_RADIUS + 1] = film_weights();
    vec4 sum = vec4(0.0);
#if defined(FILM_SHARED)
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    for (int d = -FILM_RADIUS; d <= FILM_RADIUS; ++d) {
        sum += weights[abs(d)] * film_rows[local.y + FILM_RADIUS + d][local.x];
    }
#elif defined(FILM_SEPARABLE)
    ivec2 axis = film_columns ? ivec2(0, 1) : ivec2(1, 0);
    for (int d = -FILM_RADIUS; d <= FILM_RADIUS; ++d) {
        sum += weights[abs(d)] * sanitize_color(texelFetch(color, clamp(x + d * axis, ivec2(0), last), 0));
    }
#else
    for (int dy = -FILM_RADIUS; dy <= FILM_RADIUS; ++dy) {
        vec4 row = vec4(0.0);
        int y = clamp(x.y + dy, 0, last.y);
        for (int dx = -FILM_RADIUS; dx <= FILM_RADIUS; ++dx) {
            row += weights[abs(dx)] * sanitize_color(texelFetch(color, ivec2(clamp(x.x + dx, 0, last.x), y), 0));
        }
        sum += weights[abs(dy)] * row;
    }
#endif
    return sum;
}

#define PASS_AT film_at
#include "common/pass_main.glsl"
