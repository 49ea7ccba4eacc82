#version 450
// SSIM reduction for sweeps, docs/spec.md §6: the sum over pixels of the SSIM map (Wang et al. 2004)
// of the luminance of two images clipped to [0, 1], Gaussian window of RADIUS = 5 (11 taps,
// σ = 1.5; WEIGHTS computed in double on the CPU and injected as a define), C1 = 0.01²,
// C2 = 0.03², one partial sum per 16 x 16 work group (added up in double on the CPU).
// NumPy twin: blurlab.metrics.ssim; C++: SsimReductionPass; test: tests/test_ssim_gpu.py.
//
// One dispatch, no intermediate textures: each work group loads the luminance of its tile plus
// a RADIUS border into shared memory, with the border mirrored as np.pad(mode="reflect") does
// (the edge texel is not repeated; the mirror repeats with period 2(n - 1), so images smaller
// than the window are handled as NumPy handles them), blurs horizontally into shared memory,
// then vertically per pixel, and reduces the SSIM map.
//
// Precision: variances are E[x²] - E[x]², which loses digits in float32 where the image is flat.
// Both are shift-invariant, so the moments are taken of x - c with c the luminance at the
// tile's center: in flat regions the shifted values are near 0 and nothing cancels.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D image_a;
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };

const int GROUP = 16;
const int SPAN = GROUP + 2 * RADIUS;  // tile plus its border, per axis
const float WEIGHT[2 * RADIUS + 1] = WEIGHTS;
const float C1 = 0.01 * 0.01;
const float C2 = 0.03 * 0.03;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);  // Rec. 709, as blurlab.metrics

shared float lum_x[SPAN * SPAN];
shared float lum_y[SPAN * SPAN];
// Horizontal Gaussian of (x, y, x², y², xy), SPAN rows by GROUP columns.
shared float row_x[SPAN * GROUP];
shared float row_y[SPAN * GROUP];
shared float row_xx[SPAN * GROUP];
shared float row_yy[SPAN * GROUP];
shared float row_xy[SPAN * GROUP];
shared float sums[GROUP * GROUP];

// np.pad(mode="reflect") index: mirror about 0 and n - 1 without repeating the edge.
int reflect_index(int i, int n) {
    if (n == 1) return 0;
    int period = 2 * (n - 1);
    i = abs(i) % period;
    return i < n ? i : period - i;
}

void main() {
    ivec2 size = textureSize(image_a, 0);
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * GROUP - RADIUS;
    uint local = gl_LocalInvocationIndex;

    for (uint i = local; i < uint(SPAN * SPAN); i += uint(GROUP * GROUP)) {
        ivec2 p = origin + ivec2(int(i) % SPAN, int(i) / SPAN);
        p = ivec2(reflect_index(p.x, size.x), reflect_index(p.y, size.y));
        lum_x[i] = dot(clamp(texelFetch(image_a, p, 0).rgb, 0.0, 1.0), LUMINANCE);
        lum_y[i] = dot(clamp(texelFetch(image_b, p, 0).rgb, 0.0, 1.0), LUMINANCE);
    }
    barrier();

    const int center = (RADIUS + GROUP / 2) * SPAN + RADIUS + GROUP / 2;
    float cx = lum_x[center], cy = lum_y[center];
    for (uint i = local; i < uint(SPAN * GROUP); i += uint(GROUP * GROUP)) {
        int row = int(i) / GROUP, column = int(i) % GROUP;
        float sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
        for (int t = 0; t <= 2 * RADIUS; ++t) {
            float x = lum_x[row * SPAN + column + t] - cx;
            float y = lum_y[row * SPAN + column + t] - cy;
            float w = WEIGHT[t];
            sx += w * x;
            sy += w * y;
            sxx += w * x * x;
            syy += w * y * y;
            sxy += w * x * y;
        }
        row_x[i] = sx;
        row_y[i] = sy;
        row_xx[i] = sxx;
        row_yy[i] = syy;
        row_xy[i] = sxy;
    }
    barrier();

    ivec2 l = ivec2(gl_LocalInvocationID.xy);
    float s = 0.0;
    if (all(lessThan(ivec2(gl_GlobalInvocationID.xy), size))) {
        float dx = 0.0, dy = 0.0, exx = 0.0, eyy = 0.0, exy = 0.0;
        for (int t = 0; t <= 2 * RADIUS; ++t) {
            int i = (l.y + t) * GROUP + l.x;
            float w = WEIGHT[t];
            dx += w * row_x[i];
            dy += w * row_y[i];
            exx += w * row_xx[i];
            eyy += w * row_yy[i];
            exy += w * row_xy[i];
        }
        float mx = cx + dx, my = cy + dy;
        float vx = exx - dx * dx, vy = eyy - dy * dy, cov = exy - dx * dy;
        s = ((2.0 * mx * my + C1) * (2.0 * cov + C2)) /
            ((mx * mx + my * my + C1) * (vx + vy + C2));
    }
    sums[local] = s;
    barrier();
    for (uint stride = uint(GROUP * GROUP / 2); stride > 0u; stride >>= 1u) {
        if (local < stride) sums[local] += sums[local + stride];
        barrier();
    }
    if (local == 0u) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = sums[0];
}
