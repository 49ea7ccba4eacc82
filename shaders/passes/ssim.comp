#version 450
// SSIM reduction for sweeps, docs/spec.md §6: the sum over pixels of the SSIM map (Wang et al. 2004)
// of the luminance of two images clipped to [0, 1] (NaN read as 0, as every pass reads colour:
// common/inputs.glsl), Gaussian window of RADIUS = 5 (11 taps, σ = 1.5; WEIGHTS computed in double
// on the CPU and injected as a define), C1 = 0.01², C2 = 0.03², one partial sum per 32 x TILE_Y
// work group (added up in double on the CPU).
// NumPy twins: blurlab.metrics.ssim and mse; C++: SsimReductionPass; tests: tests/test_ssim_gpu.py.
//
// Variants (defines, 0 or 1):
//   SQUARED_ERROR  the same dispatch also sums the squared error of blurlab.metrics.mse (RGB
//                  clipped to [0, 1]) over the tile's pixels, from the texels it loads for the
//                  luminance anyway: each group writes two partials, (SSIM, squared error),
//                  then its ticket.
//   PREPARE        no reduction: from one image (a reference) writes, per pixel, its clipped
//                  colour and luminance (colour_luminance) and the Gaussian mean and variance of
//                  its luminance (reference_moments), for PREPARED.
//   PREPARED       with SQUARED_ERROR: image_a is a PREPARE'd colour_luminance and binding 2
//                  its reference_moments, so a pair blurs three moments (y, y², xy), not five.
//
// One dispatch, no intermediate textures: each work group loads the luminance of its 32 x TILE_Y
// tile plus a RADIUS border into shared memory once, with the border mirrored as
// np.pad(mode="reflect") does (the edge texel is not repeated; the mirror repeats with period
// 2(n - 1), so images smaller than the window are handled as NumPy handles them; tiles away from
// the edges skip the mirror's integer divisions), blurs horizontally into shared memory, then
// vertically, and reduces the SSIM map. In the vertical blur each invocation computes ROWS
// pixels down one column: it reads the ROWS + 2 RADIUS row moments once and adds each into every
// output it touches, so shared-memory reads per pixel fall from 11 to (ROWS + 10) / ROWS and
// there are ROWS times fewer invocations to sum. Every output adds its taps in the same order
// whatever ROWS is. The group's sum is common/ssim.glsl's group_sum: a subgroup add and one
// barrier where the driver has GL_KHR_shader_subgroup_arithmetic (the H100), else a tree.
//
// Precision: variances are E[x²] - E[x]², which loses digits in float32 where the image is flat.
// Both are shift-invariant, so the moments are taken of x - c with c the luminance at the
// tile's center: in flat regions the shifted values are near 0 and nothing cancels.
#if defined(GL_KHR_shader_subgroup_arithmetic)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#define SUBGROUP_SUM 1
#endif
#define GROUP_INVOCATIONS (32 * (TILE_Y / ROWS))
#include "common/inputs.glsl"
#include "common/ssim.glsl"

const int TILE_X = 32, THREADS_Y = TILE_Y / ROWS, INVOCATIONS = GROUP_INVOCATIONS;
layout(local_size_x = TILE_X, local_size_y = THREADS_Y) in;
#include "common/ssim_group_sum.glsl"
layout(binding = 0) uniform sampler2D image_a;
#if PREPARE
const int LUMS = 1;  // planes: x (row moments: MOMENTS, common/ssim.glsl)
layout(rgba32f, binding = 0) writeonly uniform image2D colour_luminance;
layout(rg32f, binding = 1) writeonly uniform image2D reference_moments;
#else
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };
uniform float reduction_ticket;  // written after each group's sums (src/passes/pair_reduction.h)
#if PREPARED
const int LUMS = 2;  // planes: x, y
layout(binding = 2) uniform sampler2D reference_moments;
#else
const int LUMS = 2;  // planes: x, y
#endif
#endif

const int SPAN_X = TILE_X + 2 * RADIUS, SPAN_Y = TILE_Y + 2 * RADIUS;  // tile and border

// One pool of shared memory, used twice: first the luminance over the tile and its border (LUMS
// planes), then the horizontal Gaussian of the MOMENTS products (planes of SPAN_Y rows by TILE_X
// columns). Sharing it keeps a 32 x 32 tile within 32 KiB (llvmpipe's limit; the two arrays side
// by side took 41 KiB). Planes keep neighbouring invocations on neighbouring banks.
const int LUM_PLANE = SPAN_Y * SPAN_X, ROW_PLANE = SPAN_Y * TILE_X;
const int POOL = LUMS * LUM_PLANE > MOMENTS * ROW_PLANE ? LUMS * LUM_PLANE : MOMENTS * ROW_PLANE;
shared float pool[POOL];

vec2 shifted_luminance(int i, vec2 c) {
    return vec2(pool[i], LUMS == 2 ? pool[LUM_PLANE + i] : 0.0) - c;
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
#if PREPARED  // colour and luminance were clipped when the reference was prepared
        vec4 prepared = texelFetch(image_a, p, 0);
        vec3 a = prepared.rgb;
        pool[i] = prepared.a;
#else
        vec3 a = clipped_colour(image_a, p);
        pool[i] = dot(a, LUMINANCE);
#endif
#if !PREPARE
        vec3 b = clipped_colour(image_b, p);
        pool[LUM_PLANE + i] = dot(b, LUMINANCE);
#endif
#if SQUARED_ERROR
        if (owned) squared_error += dot(a - b, a - b);
#endif
    }
    barrier();

    const int center = (RADIUS + TILE_Y / 2) * SPAN_X + RADIUS + TILE_X / 2;
    const vec2 c = shifted_luminance(center, vec2(0.0));
    // Each invocation blurs up to ITEMS row positions into registers, then, once every
    // invocation has read the luminance, writes them over it.
    const int ITEMS = (ROW_PLANE + INVOCATIONS - 1) / INVOCATIONS;
    float row[ITEMS][MOMENTS];
    for (int k = 0; k < ITEMS; ++k) {
        int i = int(local) + k * INVOCATIONS;
        for (int j = 0; j < MOMENTS; ++j) row[k][j] = 0.0;
        if (i < ROW_PLANE) {
            int start = (i / TILE_X) * SPAN_X + i % TILE_X;
            for (int t = 0; t <= 2 * RADIUS; ++t) {
                float[MOMENTS] v = products(shifted_luminance(start + t, c));
                for (int j = 0; j < MOMENTS; ++j) row[k][j] += WEIGHT[t] * v[j];
            }
        }
    }
    barrier();
    for (int k = 0; k < ITEMS; ++k) {
        int i = int(local) + k * INVOCATIONS;
        if (i < ROW_PLANE) {
            for (int j = 0; j < MOMENTS; ++j) pool[j * ROW_PLANE + i] = row[k][j];
        }
    }
    barrier();

    // Rows first_row .. first_row + ROWS - 1 of column x of the tile.
    int x = int(gl_LocalInvocationID.x), first_row = int(gl_LocalInvocationID.y) * ROWS;
    float m[ROWS][MOMENTS];
    for (int o = 0; o < ROWS; ++o) {
        for (int j = 0; j < MOMENTS; ++j) m[o][j] = 0.0;
    }
    for (int r = 0; r < ROWS + 2 * RADIUS; ++r) {
        int i = (first_row + r) * TILE_X + x;
        float moments[MOMENTS];
        for (int j = 0; j < MOMENTS; ++j) moments[j] = pool[j * ROW_PLANE + i];
        for (int o = 0; o < ROWS; ++o) {
            int t = r - o;  // this row's tap for output row first_row + o
            if (t >= 0 && t <= 2 * RADIUS) {
                for (int j = 0; j < MOMENTS; ++j) m[o][j] += WEIGHT[t] * moments[j];
            }
        }
    }
#if PREPARE
    for (int o = 0; o < ROWS; ++o) {
        ivec2 p = tile + ivec2(x, first_row + o);
        if (all(lessThan(p, size))) {
            float d = m[o][0];
            imageStore(reference_moments, p, vec4(c.x + d, m[o][1] - d * d, 0.0, 0.0));
            vec3 a = clipped_colour(image_a, p);
            imageStore(colour_luminance, p, vec4(a, dot(a, LUMINANCE)));
        }
    }
#else
    float s = 0.0;
    for (int o = 0; o < ROWS; ++o) {
        ivec2 p = tile + ivec2(x, first_row + o);
        if (all(lessThan(p, size))) {
#if PREPARED
            vec2 reference = texelFetch(reference_moments, p, 0).xy;  // (mean, variance)
            vec2 d = vec2(reference.x - c.x, m[o][0]);
            float vx = reference.y, vy = m[o][1] - d.y * d.y, cov = m[o][2] - d.x * d.y;
#else
            vec2 d = vec2(m[o][0], m[o][1]);
            float vx = m[o][2] - d.x * d.x, vy = m[o][3] - d.y * d.y, cov = m[o][4] - d.x * d.y;
#endif
            vec2 mean = c + d;
            s += ssim_value(mean, vx, vy, cov);
        }
    }
#if SQUARED_ERROR
    Sums total = group_sum(vec2(s, squared_error), int(local));
#else
    Sums total = group_sum(s, int(local));
#endif
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
#if SQUARED_ERROR
    if (local == 0u) {
        partials[3u * group] = total.x;
        partials[3u * group + 1u] = total.y;
        partials[3u * group + 2u] = reduction_ticket;
    }
#else
    if (local == 0u) {
        partials[2u * group] = total;
        partials[2u * group + 1u] = reduction_ticket;
    }
#endif
#endif
}
