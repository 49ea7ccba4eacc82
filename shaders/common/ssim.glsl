// What the two SSIM reduction shaders share (docs/spec.md §6): passes/ssim.comp (32-pixel-wide
// tiles blurred in shared memory) and passes/ssim_strip.comp (each invocation walks one column).
// Needs RADIUS, WEIGHTS (the normalized Gaussian taps as a GLSL float array), PREPARE, PREPARED
// and SQUARED_ERROR defined. NumPy twin: blurlab.metrics.ssim.

const float WEIGHT[2 * RADIUS + 1] = WEIGHTS;
const float C1 = 0.01 * 0.01;
const float C2 = 0.03 * 0.03;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);  // Rec. 709, as blurlab.metrics

#if PREPARE
const int MOMENTS = 2;  // x, x²
#elif PREPARED
const int MOMENTS = 3;  // y, y², xy: the reference's x and x² were blurred when it was prepared
#else
const int MOMENTS = 5;  // x, y, x², y², xy
#endif

// The products whose Gaussian means the SSIM needs, of the shifted luminance pair v.
float[MOMENTS] products(vec2 v) {
#if PREPARE
    return float[MOMENTS](v.x, v.x * v.x);
#elif PREPARED
    return float[MOMENTS](v.y, v.y * v.y, v.x * v.y);
#else
    return float[MOMENTS](v.x, v.y, v.x * v.x, v.y * v.y, v.x * v.y);
#endif
}

// np.pad(mode="reflect") index: mirror about 0 and n - 1 without repeating the edge.
int reflect_index(int i, int n) {
    if (n == 1) return 0;
    int period = 2 * (n - 1);
    i = abs(i) % period;
    return i < n ? i : period - i;
}

// One pixel of the SSIM map (Wang et al. 2004) from the Gaussian means, variances and covariance.
float ssim_value(vec2 mean, float vx, float vy, float cov) {
    return ((2.0 * mean.x * mean.y + C1) * (2.0 * cov + C2)) /
           ((mean.x * mean.x + mean.y * mean.y + C1) * (vx + vy + C2));
}
