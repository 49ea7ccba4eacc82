#version 450
// Squared-error reduction for sweeps, docs/spec.md §6: the sum over pixels and RGB channels of
// (clamp(a, 0, 1) - clamp(b, 0, 1))^2, NaN read as 0 (common/inputs.glsl), one partial sum per
// 32 x 32 work group (written to a buffer and added up in double precision on the CPU), so a
// sweep reads back a few kilobytes instead of two images. NumPy twin: blurlab.metrics.mse.
// Each invocation adds ROWS pixels of its column, 8 rows apart (rows of a warp stay contiguous):
// a quarter of the invocations and a quarter of the partial sums that one pixel each would need.
#include "common/inputs.glsl"

const int TILE = 32, THREADS_Y = 8, ROWS = TILE / THREADS_Y;
layout(local_size_x = TILE, local_size_y = THREADS_Y) in;
layout(binding = 0) uniform sampler2D image_a;
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };
uniform float reduction_ticket;  // written after each group's sum (src/passes/pair_reduction.h)
shared float sums[TILE * THREADS_Y];

void main() {
    ivec2 size = textureSize(image_a, 0);
    ivec2 p = ivec2(gl_WorkGroupID.xy) * TILE + ivec2(gl_LocalInvocationID.xy);
    uint i = gl_LocalInvocationIndex;
    float e = 0.0;
    for (int r = 0; r < ROWS; ++r, p.y += THREADS_Y) {
        if (all(lessThan(p, size))) {
            vec3 d = clipped_colour(image_a, p) - clipped_colour(image_b, p);
            e += dot(d, d);
        }
    }
    sums[i] = e;
    barrier();
    for (uint stride = uint(TILE * THREADS_Y / 2); stride > 0u; stride >>= 1u) {
        if (i < stride) sums[i] += sums[i + stride];
        barrier();
    }
    if (i == 0u) {
        uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        partials[2u * group] = sums[0];
        partials[2u * group + 1u] = reduction_ticket;
    }
}
