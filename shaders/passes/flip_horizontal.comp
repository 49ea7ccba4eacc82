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
// Each invocation converts its taps to YCxCz itself: a shared-memory row cache (64 x 4 groups)
// was 2-4x slower on llvmpipe, where barriers are costly, and the GPU's texture cache serves
// the neighbours' reads anyway.
#include "common/flip.glsl"
#include "common/inputs.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D reference;
layout(binding = 1) uniform sampler2D test;
layout(binding = 0, rgba32f) uniform writeonly image2D reference_color;
layout(binding = 1, rgba32f) uniform writeonly image2D reference_features;
layout(binding = 2, rgba32f) uniform writeonly image2D test_color;
layout(binding = 3, rgba32f) uniform writeonly image2D test_features;

const int RADIUS = max(CSF_RADIUS, FEATURE_RADIUS);
const float K_Y[] = CSF_Y, K_CX[] = CSF_CX, K_CZ1[] = CSF_CZ1, K_CZ2[] = CSF_CZ2;
const float K_G[] = FEATURE_G, K_D[] = FEATURE_D, K_DD[] = FEATURE_DD;

void main() {
    ivec2 size = textureSize(reference, 0);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    vec4 color_r = vec4(0.0), color_t = vec4(0.0);
    vec3 features_r = vec3(0.0), features_t = vec3(0.0);
    for (int t = -RADIUS; t <= RADIUS; ++t) {
        ivec2 q = ivec2(clamp(p.x + t, 0, size.x - 1), p.y);
        // NaN reads as 0, as every pass reads colour (common/inputs.glsl).
        vec3 r = linear_to_ycxcz(sanitize_color(texelFetch(reference, q, 0)).rgb);
        vec3 e = linear_to_ycxcz(sanitize_color(texelFetch(test, q, 0)).rgb);
        int c = t + CSF_RADIUS;
        if (c >= 0 && c <= 2 * CSF_RADIUS) {
            vec4 k = vec4(K_Y[c], K_CX[c], K_CZ1[c], K_CZ2[c]);
            color_r += k * r.xyzz;
            color_t += k * e.xyzz;
        }
        int f = t + FEATURE_RADIUS;
        if (f >= 0 && f <= 2 * FEATURE_RADIUS) {
            vec3 k = vec3(K_G[f], K_D[f], K_DD[f]);
            features_r += k * ((r.x + 16.0) / 116.0);
            features_t += k * ((e.x + 16.0) / 116.0);
        }
    }
    imageStore(reference_color, p, color_r);
    imageStore(reference_features, p, vec4(features_r, 0.0));
    imageStore(test_color, p, color_t);
    imageStore(test_features, p, vec4(features_t, 0.0));
}
