#version 450
// SSIM reduction, docs/spec.md §6, the "strip" layouts of blurlab.metrics.SSIM_LAYOUTS: the same
// sums as passes/ssim.comp (mean SSIM map of the clipped luminance, Gaussian window of RADIUS = 5,
// np.pad(mode="reflect") borders; optionally the squared error of the same texels), computed
// with less shared-memory traffic and fewer barriers.
// NumPy twins: blurlab.metrics.ssim and mse; C++: SsimReductionPass; tests: tests/test_ssim_gpu.py.
//
// A work group of GROUP_X invocations owns a strip GROUP_X pixels wide and STRIP rows tall; each
// invocation owns one column of it and walks down the STRIP + 2 RADIUS input rows:
//   - the group loads BATCH rows of the luminance pair (strip and a RADIUS border left and right)
//     into one of two shared buffers while it blurs the previous BATCH rows from the other, so
//     there is one barrier per BATCH rows and the texture reads of the next batch are in flight
//     during the arithmetic of this one;
//   - each invocation blurs its column's row horizontally (2 RADIUS + 1 reads from shared memory)
//     and adds the result, with the tap weight of each, into the 2 RADIUS + 1 output rows it
//     reaches, 2 RADIUS of them kept in registers: pending[k] is the output row centred 2 RADIUS
//     - k rows above the newest input row, so the arriving row completes pending[0], and every
//     other entry moves up one place as it takes its tap (an add, no copy);
//   - the SSIM map is summed per invocation in registers, then over the group with a subgroup
//     add (GL_KHR_shader_subgroup_arithmetic, where the driver has it) or a shared-memory tree.
// Precision: as in ssim.comp, the moments are of x - c, which keeps E[x²] - E[x]² from cancelling
// in float32 where the image is flat. Every tap of one output pixel must share its c, so each
// invocation takes its own, the pair at its column's pixel in the strip's middle row: a shift
// per strip was up to 6.9e-6 from NumPy on the five scenes' blurred 160 x 90 frames, one per
// column at most 4.2e-7 (tiles: 9.7e-7).
//
// Variants (defines, 0 or 1), as in passes/ssim.comp but for the prepared reference's textures:
//   SQUARED_ERROR  also sums the squared clipped RGB error of each owned pixel, from the texels
//                  loaded for the luminance; each group writes (SSIM, squared error).
//   PREPARE        from one image (a reference) writes colour_mean (RGBA32F: clipped RGB, Gaussian
//                  mean of the luminance) and luminance_variance (RG32F: luminance, Gaussian
//                  variance of the luminance).
//   PREPARED       with SQUARED_ERROR: image_a is a PREPARE'd colour_mean and binding 2 its
//                  luminance_variance. The border rows and columns read only the 8-byte
//                  luminance_variance texel of the reference (ssim.comp's prepared layout reads
//                  16 bytes there); colour_mean is read once per owned pixel, and the mean and
//                  variance wait in shared memory (STASH) for their output RADIUS rows later.
#if defined(GL_KHR_shader_subgroup_arithmetic)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#define SUBGROUP_SUM 1
#endif
#define GROUP_INVOCATIONS GROUP_X
#include "common/inputs.glsl"
#include "common/ssim.glsl"

layout(local_size_x = GROUP_X) in;
#include "common/ssim_group_sum.glsl"
const int TAPS = 2 * RADIUS + 1;
const int SPAN_X = GROUP_X + 2 * RADIUS, INPUT_ROWS = STRIP + 2 * RADIUS;
#if PREPARED && GROUP_X <= 128
// The reference's (mean, variance) of the owned texels go to shared memory as they are loaded,
// for the output pixel RADIUS rows later: no second texture read per pixel. The stash keeps
// three batches: the one being blurred, the one before (RADIUS <= BATCH rows back reach no
// further) and the next, stored while slower invocations still read the other two. With the
// luminance buffers it fits llvmpipe's 32 KiB up to 128 invocations.
#define STASH 1
#else
#define STASH 0
#endif
// Rows per barrier: the two luminance buffers (and the stash) stay within 32 KiB.
const int BATCH = GROUP_X > 128 ? 4 : (STASH != 0 && GROUP_X > 64 ? RADIUS : 8);
const int BATCHES = (INPUT_ROWS + BATCH - 1) / BATCH;
const int BATCH_TEXELS = BATCH * SPAN_X;
const int LOADS = (BATCH_TEXELS + GROUP_X - 1) / GROUP_X;  // texels per invocation per batch

layout(binding = 0) uniform sampler2D image_a;
#if PREPARE
layout(rgba32f, binding = 0) writeonly uniform image2D colour_mean;
layout(rg32f, binding = 1) writeonly uniform image2D luminance_variance;
#define Pair float  // the reference's luminance x
#else
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };
uniform float reduction_ticket;  // written after each group's sums (src/passes/pair_reduction.h)
#if PREPARED
layout(binding = 2) uniform sampler2D luminance_variance;
#endif
#define Pair vec2  // (x, y)
#endif

shared Pair rows[2][BATCH][SPAN_X];  // the luminance pair, two batches
#if STASH
shared vec2 stash[3][BATCH][GROUP_X];  // the reference's (mean, variance) at owned texels
#endif

ivec2 size, tile, origin;  // origin: the strip's first input texel (its border included)
bool mirror;               // some input texel lies outside the image

// The luminance pair at image texel p; adds its squared error when `owned` (and, of a prepared
// reference, gives its (mean, variance) there).
Pair pair_at(ivec2 p, bool owned, inout float squared_error, out vec2 reference_stats) {
    reference_stats = vec2(0.0);
#if PREPARE
    return dot(clipped_colour(image_a, p), LUMINANCE);
#else
    vec3 b = clipped_colour(image_b, p);
#if PREPARED
    vec2 x_variance = texelFetch(luminance_variance, p, 0).xy;
    if (owned) {
        vec4 colour_mean = texelFetch(image_a, p, 0);  // clipped when the reference was prepared
        vec3 a = colour_mean.rgb;
        squared_error += dot(a - b, a - b);
        reference_stats = vec2(colour_mean.a, x_variance.y);
    }
    float x = x_variance.x;
#else
    vec3 a = clipped_colour(image_a, p);
    float x = dot(a, LUMINANCE);
    if (SQUARED_ERROR != 0 && owned) squared_error += dot(a - b, a - b);
#endif
    return vec2(x, dot(b, LUMINANCE));
#endif
}

// The pair of texel i of batch `batch` (0 past the input rows). The strip owns the texels inside
// itself and the image: each pixel's squared error counts once, mirrored texels' never.
Pair load_pair(int i, int batch, inout float squared_error, out vec2 reference_stats) {
    reference_stats = vec2(0.0);
    ivec2 q = ivec2(i % SPAN_X, batch * BATCH + i / SPAN_X);
    if (i >= BATCH_TEXELS || q.y >= INPUT_ROWS) return Pair(0.0);
    ivec2 p = origin + q;
    bool owned = q.x >= RADIUS && q.x < RADIUS + GROUP_X && q.y >= RADIUS &&
                 q.y < RADIUS + STRIP && all(lessThan(p, size));
    if (mirror) p = ivec2(reflect_index(p.x, size.x), reflect_index(p.y, size.y));
    return pair_at(p, owned, squared_error, reference_stats);
}

// Stores texel i of batch `batch`, loaded as (pair, reference_stats), into its buffers.
void stage(int batch, int i, Pair pair, vec2 reference_stats) {
    if (i >= BATCH_TEXELS) return;
    rows[batch & 1][i / SPAN_X][i % SPAN_X] = pair;
#if STASH
    int x = i % SPAN_X - RADIUS;
    if (x >= 0 && x < GROUP_X) stash[batch % 3][i / SPAN_X][x] = reference_stats;
#endif
}

// The SSIM at pixel p from its Gaussian moments m of the shifted pair and, against a prepared
// reference, the reference's (mean, variance) there (PREPARE: writes the reference's textures
// and returns 0).
float finish_pixel(float m[MOMENTS], ivec2 p, Pair c, vec2 reference_stats) {
#if PREPARE
    vec3 a = clipped_colour(image_a, p);
    float d = m[0];
    imageStore(colour_mean, p, vec4(a, c + d));
    imageStore(luminance_variance, p, vec4(dot(a, LUMINANCE), m[1] - d * d, 0.0, 0.0));
    return 0.0;
#else
#if PREPARED
    float mean_x = reference_stats.x, vx = reference_stats.y;
    vec2 d = vec2(mean_x - c.x, m[0]);
    float vy = m[1] - d.y * d.y, cov = m[2] - d.x * d.y;
#else
    vec2 d = vec2(m[0], m[1]);
    float vx = m[2] - d.x * d.x, vy = m[3] - d.y * d.y, cov = m[4] - d.x * d.y;
#endif
    return ssim_value(c + d, vx, vy, cov);
#endif
}

void main() {
    size = textureSize(image_a, 0);
    tile = ivec2(gl_WorkGroupID.xy) * ivec2(GROUP_X, STRIP);
    origin = tile - RADIUS;
    mirror = any(lessThan(origin, ivec2(0))) ||
             any(greaterThan(origin + ivec2(SPAN_X, INPUT_ROWS), size));
    int local = int(gl_LocalInvocationID.x);

    // c: this column's shift, the pair at its pixel in the strip's middle row (cut at the image).
    int column = tile.x + local;
    float squared_error = 0.0, unused = 0.0;
    vec2 unused_stats;
    Pair c = pair_at(min(ivec2(column, tile.y + STRIP / 2), size - 1), false, unused, unused_stats);

    Pair staged[LOADS];
    vec2 staged_stats[LOADS];
    for (int k = 0; k < LOADS; ++k)
        staged[k] = load_pair(local + k * GROUP_X, 0, squared_error, staged_stats[k]);
    for (int k = 0; k < LOADS; ++k) stage(0, local + k * GROUP_X, staged[k], staged_stats[k]);
    barrier();

    float pending[2 * RADIUS][MOMENTS];  // the output rows 2 RADIUS .. 1 rows above the newest
    for (int k = 0; k < 2 * RADIUS; ++k) {
        for (int j = 0; j < MOMENTS; ++j) pending[k][j] = 0.0;
    }
    float s = 0.0;
    for (int batch = 0; batch < BATCHES; ++batch) {
        int current = batch & 1;
        bool more = batch + 1 < BATCHES;
        if (more) {  // issued now, stored after this batch's arithmetic
            for (int k = 0; k < LOADS; ++k)
                staged[k] = load_pair(local + k * GROUP_X, batch + 1, squared_error, staged_stats[k]);
        }
        for (int r = 0; r < BATCH; ++r) {
            int input_row = batch * BATCH + r;
            if (input_row >= INPUT_ROWS) break;
            float h[MOMENTS];
            for (int j = 0; j < MOMENTS; ++j) h[j] = 0.0;
            for (int t = 0; t < TAPS; ++t) {
                Pair v = rows[current][r][local + t] - c;
#if PREPARE
                float[MOMENTS] products_t = products(vec2(v, 0.0));
#else
                float[MOMENTS] products_t = products(v);
#endif
                for (int j = 0; j < MOMENTS; ++j) h[j] += WEIGHT[t] * products_t[j];
            }
            // Output row input_row - 2 RADIUS takes its last tap; the others move up a place,
            // and the row input_row - RADIUS (no tap yet) enters with its first.
            float done[MOMENTS];
            for (int j = 0; j < MOMENTS; ++j) done[j] = pending[0][j] + WEIGHT[2 * RADIUS] * h[j];
            for (int k = 0; k < 2 * RADIUS - 1; ++k) {
                for (int j = 0; j < MOMENTS; ++j)
                    pending[k][j] = pending[k + 1][j] + WEIGHT[2 * RADIUS - 1 - k] * h[j];
            }
            for (int j = 0; j < MOMENTS; ++j) pending[2 * RADIUS - 1][j] = WEIGHT[0] * h[j];
            ivec2 p = ivec2(column, tile.y + input_row - 2 * RADIUS);
            if (input_row >= 2 * RADIUS && all(lessThan(p, size))) {
                vec2 reference_stats = vec2(0.0);
#if STASH  // loaded RADIUS rows ago: in this batch or the one before
                int owned_row = input_row - RADIUS;
                reference_stats = stash[(owned_row / BATCH) % 3][owned_row % BATCH][local];
#elif PREPARED
                reference_stats = vec2(texelFetch(image_a, p, 0).a,
                                       texelFetch(luminance_variance, p, 0).y);
#endif
                s += finish_pixel(done, p, c, reference_stats);
            }
        }
        if (more) {
            for (int k = 0; k < LOADS; ++k)
                stage(batch + 1, local + k * GROUP_X, staged[k], staged_stats[k]);
        }
        barrier();
    }

#if !PREPARE
#if SQUARED_ERROR
    Sums total = group_sum(vec2(s, squared_error), local);
#else
    Sums total = group_sum(s, local);
#endif
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
#if SQUARED_ERROR
    if (local == 0) {
        partials[3u * group] = total.x;
        partials[3u * group + 1u] = total.y;
        partials[3u * group + 2u] = reduction_ticket;
    }
#else
    if (local == 0) {
        partials[2u * group] = total;
        partials[2u * group + 1u] = reduction_ticket;
    }
#endif
#endif
}
