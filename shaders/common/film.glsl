// The film filter's kernel (docs/spec.md §17.6, step 4), for passes/film_filter.glsl and for the
// filter folded into a pass (common/film_in_pass.glsl): a Gaussian of standard deviation
// film_filter px out to FILM_RADIUS = ceil(3σ) px, a #define the method sets so that the loops
// unroll. The Gaussian and the clamping to the image are separable: the 2D weight of (dx, dy) is
// w(dx)·w(dy) of the normalised 1D kernel w.
uniform float film_filter;  // σ, px

// w at distances 0 .. FILM_RADIUS, normalised over -FILM_RADIUS .. FILM_RADIUS.
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
