#version 450
// SSIM reduction for sweeps, docs/spec.md §6: the sum over pixels of the SSIM map (Wang et al. 2004)
// of the luminance of two images clipped to [0, 1], Gaussian window of RADIUS = 5 (11 taps,
// σ = 1.5; WEIGHTS computed in double on the CPU and injected as a define), C1 = 0.01²,
// C2 = 0.03², one partial sum per 32 x 16 work group (added up in double on the CPU).
// NumPy twin: blurlab.metrics.ssim; C++: SsimReductionPass; test: tests/test_ssim_gpu.py.
//
// One dispatch, no intermediate textures: each work group loads the luminance pair of its
// 32 x 16 tile plus a RADIUS border into shared memory once (2.1 texel reads per pixel and
// image; a 16 x 16 tile needed 2.6), with the border mirrored as np.pad(mode="reflect") does
// (the edge texel is not repeated; the mirror repeats with period 2(n - 1), so images smaller
// than the window are handled as NumPy handles them; tiles away from the edges skip the
// mirror's integer divisions), blurs horizontally into shared memory, then vertically per
// pixel, and reduces the SSIM map.
//
// Precision: variances are E[x²] - E[x]², which loses digits in float32 where the image is flat.
// Both are shift-invariant, so the moments are taken of x - c with c the luminance at the
// tile's center: in flat regions the shifted values are near 0 and nothing cancels.
layout(local_size_x = 32, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D image_a;
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };

const int TILE_X = 32, TILE_Y = 16, INVOCATIONS = TILE_X * TILE_Y;
const int SPAN_X = TILE_X + 2 * RADIUS, SPAN_Y = TILE_Y + 2 * RADIUS;  // tile and border
const float WEIGHT[2 * RADIUS + 1] = WEIGHTS;
const float C1 = 0.01 * 0.01;
const float C2 = 0.03 * 0.03;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);  // Rec. 709, as blurlab.metrics

shared vec2 lum[SPAN_Y * SPAN_X];  // (x, y) luminance of the two images
// Horizontal Gaussian of (x, y, x², y²) and of xy, SPAN_Y rows by TILE_X columns.
shared vec4 row_moments[SPAN_Y * TILE_X];
shared float row_xy[SPAN_Y * TILE_X];
shared float sums[INVOCATIONS];

// np.pad(mode="reflect") index: mirror about 0 and n - 1 without repeating the edge.
int reflect_index(int i, int n) {
    if (n == 1) return 0;
    int period = 2 * (n - 1);
    i = abs(i) % period;
    return i < n ? i : period - i;
}

void main() {
    ivec2 size = textureSize(image_a, 0);
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * ivec2(TILE_X, TILE_Y) - RADIUS;
    bool inside = all(greaterThanEqual(origin, ivec2(0))) &&
                  all(lessThanEqual(origin + ivec2(SPAN_X, SPAN_Y), size));
    uint local = gl_LocalInvocationIndex;

    for (uint i = local; i < uint(SPAN_X * SPAN_Y); i += uint(INVOCATIONS)) {
        ivec2 p = origin + ivec2(int(i) % SPAN_X, int(i) / SPAN_X);
        if (!inside) p = ivec2(reflect_index(p.x, size.x), reflect_index(p.y, size.y));
        lum[i] = vec2(dot(clamp(texelFetch(image_a, p, 0).rgb, 0.0, 1.0), LUMINANCE),
                      dot(clamp(texelFetch(image_b, p, 0).rgb, 0.0, 1.0), LUMINANCE));
    }
    barrier();

    const vec2 c = lum[(RADIUS + TILE_Y / 2) * SPAN_X + RADIUS + TILE_X / 2];
    for (uint i = local; i < uint(SPAN_Y * TILE_X); i += uint(INVOCATIONS)) {
        int row = int(i) / TILE_X, column = int(i) % TILE_X;
        vec4 m = vec4(0.0);
        float sxy = 0.0;
        for (int t = 0; t <= 2 * RADIUS; ++t) {
            vec2 v = lum[row * SPAN_X + column + t] - c;
            float w = WEIGHT[t];
            m += w * vec4(v, v * v);
            sxy += w * v.x * v.y;
        }
        row_moments[i] = m;
        row_xy[i] = sxy;
    }
    barrier();

    ivec2 l = ivec2(gl_LocalInvocationID.xy);
    float s = 0.0;
    if (all(lessThan(ivec2(gl_GlobalInvocationID.xy), size))) {
        vec4 m = vec4(0.0);
        float exy = 0.0;
        for (int t = 0; t <= 2 * RADIUS; ++t) {
            int i = (l.y + t) * TILE_X + l.x;
            float w = WEIGHT[t];
            m += w * row_moments[i];
            exy += w * row_xy[i];
        }
        vec2 d = m.xy, mean = c + d;
        float vx = m.z - d.x * d.x, vy = m.w - d.y * d.y, cov = exy - d.x * d.y;
        s = ((2.0 * mean.x * mean.y + C1) * (2.0 * cov + C2)) /
            ((mean.x * mean.x + mean.y * mean.y + C1) * (vx + vy + C2));
    }
    sums[local] = s;
    barrier();
    for (uint stride = uint(INVOCATIONS / 2); stride > 0u; stride >>= 1u) {
        if (local < stride) sums[local] += sums[local + stride];
        barrier();
    }
    if (local == 0u) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = sums[0];
}
