#version 450
// LDR-FLIP, horizontal half of its separable filters (docs/spec.md §6.1; Andersson et al. 2020).
// NumPy twin: blurlab.twins.flip (flip_map's `separable` calls, across); the pass's Python side
// is blurlab.metrics.gpu_flip; test: tests/test_flip_gpu.py.
//
// For each of the two images (linear RGB, clipped to [0, 1]) and each pixel, the rows of
//   *_color:    Y, Cx and the two Cz terms of YCxCz filtered across by the contrast-sensitivity
//               kernels CSF_Y, CSF_CX, CSF_CZ1, CSF_CZ2 (2 CSF_RADIUS + 1 taps each);
//   *_features: the normalized luminance (Y + 16) / 116 filtered across by the Gaussian, its
//               first and its second derivative (FEATURE_G, FEATURE_D, FEATURE_DD).
// flip_error.comp filters these down the columns. Past the image edge the edge pixel repeats.
//
// A work group converts a row segment of both images to YCxCz once, into shared memory, and
// every invocation reads its taps from there.
#include "common/flip.glsl"

layout(local_size_x = 64, local_size_y = 4) in;
layout(binding = 0) uniform sampler2D reference;
layout(binding = 1) uniform sampler2D test;
layout(binding = 0, rgba32f) uniform writeonly image2D reference_color;
layout(binding = 1, rgba32f) uniform writeonly image2D reference_features;
layout(binding = 2, rgba32f) uniform writeonly image2D test_color;
layout(binding = 3, rgba32f) uniform writeonly image2D test_features;

const int WIDTH = 64, ROWS = 4;
const int RADIUS = max(CSF_RADIUS, FEATURE_RADIUS);
const int SPAN = WIDTH + 2 * RADIUS;
const float K_Y[] = CSF_Y, K_CX[] = CSF_CX, K_CZ1[] = CSF_CZ1, K_CZ2[] = CSF_CZ2;
const float K_G[] = FEATURE_G, K_D[] = FEATURE_D, K_DD[] = FEATURE_DD;

shared vec3 ycxcz[2][ROWS][SPAN];

void filter_row(int image, int row, int column, ivec2 p) {
    vec4 color = vec4(0.0);
    for (int t = 0; t <= 2 * CSF_RADIUS; ++t) {
        vec3 c = ycxcz[image][row][column + RADIUS - CSF_RADIUS + t];
        color += vec4(K_Y[t] * c.x, K_CX[t] * c.y, K_CZ1[t] * c.z, K_CZ2[t] * c.z);
    }
    vec3 features = vec3(0.0);
    for (int t = 0; t <= 2 * FEATURE_RADIUS; ++t) {
        float y = (ycxcz[image][row][column + RADIUS - FEATURE_RADIUS + t].x + 16.0) / 116.0;
        features += y * vec3(K_G[t], K_D[t], K_DD[t]);
    }
    if (image == 0) {
        imageStore(reference_color, p, color);
        imageStore(reference_features, p, vec4(features, 0.0));
    } else {
        imageStore(test_color, p, color);
        imageStore(test_features, p, vec4(features, 0.0));
    }
}

void main() {
    ivec2 size = textureSize(reference, 0);
    int row = int(gl_LocalInvocationID.y);
    int y = min(int(gl_GlobalInvocationID.y), size.y - 1);
    int x0 = int(gl_WorkGroupID.x) * WIDTH - RADIUS;
    for (int i = int(gl_LocalInvocationID.x); i < SPAN; i += WIDTH) {
        ivec2 q = ivec2(clamp(x0 + i, 0, size.x - 1), y);
        ycxcz[0][row][i] = linear_to_ycxcz(texelFetch(reference, q, 0).rgb);
        ycxcz[1][row][i] = linear_to_ycxcz(texelFetch(test, q, 0).rgb);
    }
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    filter_row(0, row, int(gl_LocalInvocationID.x), p);
    filter_row(1, row, int(gl_LocalInvocationID.x), p);
}
