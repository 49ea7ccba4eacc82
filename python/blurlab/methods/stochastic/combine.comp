#version 450
// stochastic, docs/spec.md §4 (the OGRE paper): K time slices; every pixel takes 4 samples at
// rotated-grid positions inside it and 4 from its edge neighbours, C = 5/32 Σ inside +
// 3/32 Σ neighbour. Sample i of pixel X comes from time quarter q = π_X(i) (a hashed
// permutation of 0..3) and, within it, slice floor((q + r) K / 4) with r hashed per (X, i):
// for K = 4 that is slice π_X(i), for K > 4 the four samples spread over the whole shutter.
// Slice l, sample position i is one render (jittered to put position i at the pixel center);
// this pass adds its share. The neighbour to the right gives its leftmost sample (i = 2), the
// one below its topmost (0), the one to the left its rightmost (1), the one above its
// bottommost (3). NumPy twin: twin.py beside it.
#include "common/inputs.glsl"
#include "common/random.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D color;  // the render of slice `slice`, position `position`
layout(binding = 0, rgba32f) uniform image2D sum;
uniform int slice;
uniform int position;
uniform int slices;  // K
uniform uint seed;

// The slice that sample i of pixel p takes.
int slice_of(ivec2 p, int i) {
    uint h = pcg(uint(p.x) ^ pcg(uint(p.y) ^ pcg(seed)));
    // π(i): a permutation of 0..3 from h (Lehmer code: 24 permutations).
    int order[4] = int[](0, 1, 2, 3);
    uint code = h % 24u;
    for (int k = 0; k < 3; ++k) {
        int j = k + int(code % uint(4 - k));
        code /= uint(4 - k);
        int t = order[k];
        order[k] = order[j];
        order[j] = t;
    }
    float r = float(pcg(h ^ uint(i + 1)) >> 8u) * (1.0 / 16777216.0);
    return min(int(floor((float(order[i]) + r) * float(slices) / 4.0)), slices - 1);
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(sum);
    if (any(greaterThanEqual(x, size))) return;
    vec4 add = vec4(0.0);
    if (slice_of(x, position) == slice) add += 5.0 / 32.0 * sanitize_color(texelFetch(color, x, 0));
    const ivec2 neighbours[4] = ivec2[](ivec2(0, 1), ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1));
    // Neighbour n gives sample n: below -> 0 (topmost), left -> 1 (rightmost),
    // right -> 2 (leftmost), above -> 3 (bottommost).
    ivec2 n = clamp(x + neighbours[position], ivec2(0), size - 1);
    if (slice_of(n, position) == slice) add += 3.0 / 32.0 * sanitize_color(texelFetch(color, n, 0));
    imageStore(sum, x, imageLoad(sum, x) + add);
}
