#version 450
// LDR-FLIP, vertical half of the filters and the per-pixel error (docs/spec.md §6.1; Andersson
// et al. 2020). NumPy twin: blurlab.twins.flip.flip_map; Python: blurlab.metrics.gpu_flip; test:
// tests/test_flip_gpu.py.
//
// Filters flip_horizontal.comp's rows down the columns (the edge row repeats past the image),
// then per pixel:
//   colour:   filtered YCxCz -> linear RGB clipped to [0, 1] -> Hunt-adjusted CIELAB; the HyAB
//             distance d of the two images; e_c = d^QC remapped so that PC·CMAX maps to PT and
//             CMAX (green against blue) to 1;
//   features: edge and point magnitudes |(∂x, ∂y)| of each image's luminance; e_f = √(Δ / √2)
//             with Δ the larger difference of the two;
//   error = e_c^(1 - e_f), written to `error` and summed per 16 x 16 work group into `partials`
//   (one texel per group; the mean is their sum over W·H, added up in double on the CPU).
#include "common/flip.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D reference_color;
layout(binding = 1) uniform sampler2D reference_features;
layout(binding = 2) uniform sampler2D test_color;
layout(binding = 3) uniform sampler2D test_features;
layout(binding = 0, r32f) uniform writeonly image2D error;
layout(binding = 1, r32f) uniform writeonly image2D partials;

const float K_Y[] = CSF_Y, K_CX[] = CSF_CX, K_CZ1[] = CSF_CZ1, K_CZ2[] = CSF_CZ2;
const float K_G[] = FEATURE_G, K_D[] = FEATURE_D, K_DD[] = FEATURE_DD;
const float QC = 0.7, PC = 0.4, PT = 0.95;

shared float sums[256];

// The filtered colour (Hunt-adjusted CIELAB) of one image at p.
vec3 filtered_lab(sampler2D rows, ivec2 p, int height) {
    vec3 c = vec3(0.0);
    for (int t = 0; t <= 2 * CSF_RADIUS; ++t) {
        vec4 h = texelFetch(rows, ivec2(p.x, clamp(p.y - CSF_RADIUS + t, 0, height - 1)), 0);
        c += vec3(K_Y[t] * h.x, K_CX[t] * h.y, K_CZ1[t] * h.z + K_CZ2[t] * h.w);
    }
    return linear_to_hunt_lab(clamp(ycxcz_to_linear(c), 0.0, 1.0));
}

// (edge, point) magnitudes of one image at p.
vec2 features(sampler2D rows, ivec2 p, int height) {
    vec4 f = vec4(0.0);  // edge x, edge y, point x, point y
    for (int t = 0; t <= 2 * FEATURE_RADIUS; ++t) {
        vec3 h = texelFetch(rows, ivec2(p.x, clamp(p.y - FEATURE_RADIUS + t, 0, height - 1)), 0).xyz;
        f += vec4(K_G[t] * h.y, K_D[t] * h.x, K_G[t] * h.z, K_DD[t] * h.x);
    }
    return vec2(length(f.xy), length(f.zw));
}

float flip_error(ivec2 p, int height) {
    float d = hyab(filtered_lab(reference_color, p, height), filtered_lab(test_color, p, height));
    float e = pow(d, QC);
    const float knee = PC * CMAX;
    float color = e < knee ? PT / knee * e : PT + (e - knee) / (CMAX - knee) * (1.0 - PT);
    vec2 delta = abs(features(reference_features, p, height) - features(test_features, p, height));
    float exponent = 1.0 - sqrt(max(delta.x, delta.y) / sqrt(2.0));
    // pow(0, y) is undefined in GLSL; as in NumPy, 0^0 = 1 and 0^y = 0 for y > 0.
    return color > 0.0 ? pow(color, exponent) : (exponent > 0.0 ? 0.0 : 1.0);
}

void main() {
    ivec2 size = imageSize(error);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    float e = 0.0;
    if (all(lessThan(p, size))) {
        e = flip_error(p, size.y);
        imageStore(error, p, vec4(e));
    }
    uint local = gl_LocalInvocationIndex;
    sums[local] = e;
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1u) {
        if (local < stride) sums[local] += sums[local + stride];
        barrier();
    }
    if (local == 0u) imageStore(partials, ivec2(gl_WorkGroupID.xy), vec4(sums[0]));
}
