#version 450
// SSIM reduction for sweeps, docs/spec.md §6: the sum over pixels of the SSIM map (Wang et al. 2004)
// of the luminance of two images clipped to [0, 1] (NaN read as 0, as every pass reads colour:
// common/inputs.glsl), Gaussian window of RADIUS = 5 (11 taps,
// σ = 1.5; WEIGHTS computed in double on the CPU and injected as a define), C1 = 0.01²,
// C2 = 0.03², one partial sum per 32 x TILE_Y work group (added up in double on the CPU).
// With SQUARED_ERROR = 1 the same dispatch also sums the squared error of blurlab.metrics.mse
// (RGB clipped to [0, 1]) over the tile's pixels, from the texels it loads for the luminance
// anyway: each group then writes two partials, (SSIM, squared error).
// NumPy twins: blurlab.metrics.ssim and mse; C++: SsimReductionPass; tests: tests/test_ssim_gpu.py.
//
// One dispatch, no intermediate textures: each work group loads the luminance pair of its
// 32 x TILE_Y tile plus a RADIUS border into shared memory once, with the border mirrored as
// np.pad(mode="reflect") does (the edge texel is not repeated; the mirror repeats with period
// 2(n - 1), so images smaller than the window are handled as NumPy handles them; tiles away from
// the edges skip the mirror's integer divisions), blurs horizontally into shared memory, then
// vertically, and reduces the SSIM map. In the vertical blur each invocation computes ROWS
// pixels down one column: it reads the ROWS + 2 RADIUS row moments once and adds each into every
// output it touches, so shared-memory reads per pixel fall from 11 to (ROWS + 10) / ROWS and
// there are ROWS times fewer invocations for the final tree reduction. Every output adds its
// taps in the same order whatever ROWS is.
//
// Precision: variances are E[x²] - E[x]², which loses digits in float32 where the image is flat.
// Both are shift-invariant, so the moments are taken of x - c with c the luminance at the
// tile's center: in flat regions the shifted values are near 0 and nothing cancels.
#include "common/inputs.glsl"

const int TILE_X = 32, THREADS_Y = TILE_Y / ROWS, INVOCATIONS = TILE_X * THREADS_Y;
layout(local_size_x = TILE_X, local_size_y = THREADS_Y) in;
layout(binding = 0) uniform sampler2D image_a;
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };

const int SPAN_X = TILE_X + 2 * RADIUS, SPAN_Y = TILE_Y + 2 * RADIUS;  // tile and border
const float WEIGHT[2 * RADIUS + 1] = WEIGHTS;
const float C1 = 0.01 * 0.01;
const float C2 = 0.03 * 0.03;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);  // Rec. 709, as blurlab.metrics

#if SQUARED_ERROR
#define Sums vec2  // (SSIM, squared error)
#else
#define Sums float
#endif

// One pool of shared memory, used twice: first the luminance of the two images over the tile and
// its border (planes x, y), then the horizontal Gaussian of x, y, x², y² and xy (five planes,
// SPAN_Y rows by TILE_X columns). Sharing it keeps a 32 x 32 tile within 32 KiB (llvmpipe's
// limit; the two arrays side by side took 41 KiB). Planes keep neighbouring invocations on
// neighbouring banks.
const int LUM_PLANE = SPAN_Y * SPAN_X, ROW_PLANE = SPAN_Y * TILE_X;
const int POOL = 2 * LUM_PLANE > 5 * ROW_PLANE ? 2 * LUM_PLANE : 5 * ROW_PLANE;
shared float pool[POOL];
shared Sums sums[INVOCATIONS];

// np.pad(mode="reflect") index: mirror about 0 and n - 1 without repeating the edge.
int reflect_index(int i, int n) {
    if (n == 1) return 0;
    int period = 2 * (n - 1);
    i = abs(i) % period;
    return i < n ? i : period - i;
}

void main() {
    ivec2 size = textureSize(image_a, 0);
    ivec2 tile = ivec2(gl_WorkGroupID.xy) * ivec2(TILE_X, TILE_Y);
    ivec2 origin = tile - RADIUS;
    bool inside = all(greaterThanEqual(origin, ivec2(0))) &&
                  all(lessThanEqual(origin + ivec2(SPAN_X, SPAN_Y), size));
    uint local = gl_LocalInvocationIndex;

#if SQUARED_ERROR
    // The pixels this group owns: its tile, cut at the image's edge.
    ivec2 owned_end = min(tile + ivec2(TILE_X, TILE_Y), size);
    float squared_error = 0.0;
#endif
    for (uint i = local; i < uint(SPAN_X * SPAN_Y); i += uint(INVOCATIONS)) {
        ivec2 p = origin + ivec2(int(i) % SPAN_X, int(i) / SPAN_X);
#if SQUARED_ERROR
        bool owned = all(greaterThanEqual(p, tile)) && all(lessThan(p, owned_end));
#endif
        if (!inside) p = ivec2(reflect_index(p.x, size.x), reflect_index(p.y, size.y));
        vec3 a = clamp(sanitize_color(texelFetch(image_a, p, 0)).rgb, 0.0, 1.0);
        vec3 b = clamp(sanitize_color(texelFetch(image_b, p, 0)).rgb, 0.0, 1.0);
        pool[i] = dot(a, LUMINANCE);
        pool[LUM_PLANE + i] = dot(b, LUMINANCE);
#if SQUARED_ERROR
        if (owned) squared_error += dot(a - b, a - b);
#endif
    }
    barrier();

    const int center = (RADIUS + TILE_Y / 2) * SPAN_X + RADIUS + TILE_X / 2;
    const vec2 c = vec2(pool[center], pool[LUM_PLANE + center]);
    // Each invocation blurs up to ITEMS row positions into registers, then, once every
    // invocation has read the luminance, writes them over it.
    const int ITEMS = (ROW_PLANE + INVOCATIONS - 1) / INVOCATIONS;
    vec4 row_m[ITEMS];
    float row_xy[ITEMS];
    for (int k = 0; k < ITEMS; ++k) {
        int i = int(local) + k * INVOCATIONS;
        row_m[k] = vec4(0.0);
        row_xy[k] = 0.0;
        if (i < ROW_PLANE) {
            int start = (i / TILE_X) * SPAN_X + i % TILE_X;
            for (int t = 0; t <= 2 * RADIUS; ++t) {
                vec2 v = vec2(pool[start + t], pool[LUM_PLANE + start + t]) - c;
                float w = WEIGHT[t];
                row_m[k] += w * vec4(v, v * v);
                row_xy[k] += w * v.x * v.y;
            }
        }
    }
    barrier();
    for (int k = 0; k < ITEMS; ++k) {
        int i = int(local) + k * INVOCATIONS;
        if (i < ROW_PLANE) {
            for (int j = 0; j < 4; ++j) pool[j * ROW_PLANE + i] = row_m[k][j];
            pool[4 * ROW_PLANE + i] = row_xy[k];
        }
    }
    barrier();

    // Rows first_row .. first_row + ROWS - 1 of column x of the tile.
    int x = int(gl_LocalInvocationID.x), first_row = int(gl_LocalInvocationID.y) * ROWS;
    vec4 m[ROWS];
    float exy[ROWS];
    for (int o = 0; o < ROWS; ++o) {
        m[o] = vec4(0.0);
        exy[o] = 0.0;
    }
    for (int r = 0; r < ROWS + 2 * RADIUS; ++r) {
        int i = (first_row + r) * TILE_X + x;
        vec4 moments = vec4(pool[i], pool[ROW_PLANE + i], pool[2 * ROW_PLANE + i],
                            pool[3 * ROW_PLANE + i]);
        float xy = pool[4 * ROW_PLANE + i];
        for (int o = 0; o < ROWS; ++o) {
            int t = r - o;  // this row's tap for output row first_row + o
            if (t >= 0 && t <= 2 * RADIUS) {
                m[o] += WEIGHT[t] * moments;
                exy[o] += WEIGHT[t] * xy;
            }
        }
    }
    float s = 0.0;
    for (int o = 0; o < ROWS; ++o) {
        if (all(lessThan(tile + ivec2(x, first_row + o), size))) {
            vec2 d = m[o].xy, mean = c + d;
            float vx = m[o].z - d.x * d.x, vy = m[o].w - d.y * d.y, cov = exy[o] - d.x * d.y;
            s += ((2.0 * mean.x * mean.y + C1) * (2.0 * cov + C2)) /
                 ((mean.x * mean.x + mean.y * mean.y + C1) * (vx + vy + C2));
        }
    }
#if SQUARED_ERROR
    sums[local] = vec2(s, squared_error);
#else
    sums[local] = s;
#endif
    barrier();
    for (uint stride = uint(INVOCATIONS / 2); stride > 0u; stride >>= 1u) {
        if (local < stride) sums[local] += sums[local + stride];
        barrier();
    }
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
#if SQUARED_ERROR
    if (local == 0u) {
        partials[2u * group] = sums[0].x;
        partials[2u * group + 1u] = sums[0].y;
    }
#else
    if (local == 0u) partials[group] = sums[0];
#endif
}
