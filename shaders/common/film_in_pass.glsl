// The compute entry point of common/pass_main.glsl under FILM_IN_PASS: PASS_AT's image written
// through the film filter of common/film.glsl with no image between them (docs/spec.md §17.6,
// "The film filter in the gather"; blurlab.methods.coverage.FILM_VARIANTS, the in_gather
// layouts). A work group of FILM_BLOCK_X x FILM_BLOCK_Y invocations owns as many output pixels.
// It evaluates PASS_AT on its block and an apron of FILM_RADIUS px, coordinates clamped to the
// image as passes/film_filter.glsl clamps its reads, into shared memory (neighbouring
// invocations on neighbouring pixels); filters there along rows, then along columns, each sum in
// the order of film_filter.glsl's FILM_SHARED layout; and writes the filtered block. A pixel in
// the aprons of two groups is evaluated by both, so PASS_AT must be a function of the pixel
// alone; the work grows by (X + 2R)(Y + 2R)/(XY) for an X x Y block. Shared memory:
// (X + 2R)(Y + 2R) vec4; the method picks blocks that fit GL's guaranteed 32 KiB.
#include "common/film.glsl"
#include "common/inputs.glsl"

layout(local_size_x = FILM_BLOCK_X, local_size_y = FILM_BLOCK_Y) in;

const ivec2 FILM_BLOCK = ivec2(FILM_BLOCK_X, FILM_BLOCK_Y);
const int FILM_APRON_X = FILM_BLOCK_X + 2 * FILM_RADIUS;  // the block and its apron
const int FILM_APRON_Y = FILM_BLOCK_Y + 2 * FILM_RADIUS;
// Each invocation filters rows y, y + FILM_BLOCK_Y, ... of its column along the row.
const int FILM_ROWS_EACH = (FILM_APRON_Y + FILM_BLOCK_Y - 1) / FILM_BLOCK_Y;
// PASS_AT on the block and apron; then, in its first FILM_BLOCK_X columns, the rows' sums.
shared vec4 film_block[FILM_APRON_Y][FILM_APRON_X];

void main() {
    ivec2 last = textureSize(color, 0) - 1;
    ivec2 apron_origin = ivec2(gl_WorkGroupID.xy) * FILM_BLOCK - FILM_RADIUS;
    for (int i = int(gl_LocalInvocationIndex); i < FILM_APRON_X * FILM_APRON_Y;
         i += FILM_BLOCK_X * FILM_BLOCK_Y) {
        ivec2 p = ivec2(i % FILM_APRON_X, i / FILM_APRON_X);
        film_block[p.y][p.x] = sanitize_color(PASS_AT(clamp(apron_origin + p, ivec2(0), last)));
    }
    barrier();

    float weights[FILM_RADIUS + 1] = film_weights();
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    // Held in registers until every invocation has read the unfiltered rows they overwrite.
    vec4 row_sums[FILM_ROWS_EACH];
    for (int k = 0; k < FILM_ROWS_EACH; ++k) {
        int r = local.y + k * FILM_BLOCK_Y;
        vec4 sum = vec4(0.0);
        if (r < FILM_APRON_Y) {
            for (int d = -FILM_RADIUS; d <= FILM_RADIUS; ++d) {
                sum += weights[abs(d)] * film_block[r][local.x + FILM_RADIUS + d];
            }
        }
        row_sums[k] = sum;
    }
    barrier();
    for (int k = 0; k < FILM_ROWS_EACH; ++k) {
        int r = local.y + k * FILM_BLOCK_Y;
        if (r < FILM_APRON_Y) film_block[r][local.x] = row_sums[k];
    }
    barrier();

    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThan(x, last))) return;
    vec4 sum = vec4(0.0);
    for (int d = -FILM_RADIUS; d <= FILM_RADIUS; ++d) {
        sum += weights[abs(d)] * film_block[local.y + FILM_RADIUS + d][local.x];
    }
    imageStore(result, x, sum);
}
