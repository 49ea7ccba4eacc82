#version 450
// HDR-FLIP, one exposure (docs/spec.md §6.2; Andersson et al. 2021): both images scaled by
// 2^exposure and tone-mapped by the ACES fit that HDR-FLIP assumes, clipped to [0, 1]. LDR-FLIP
// (flip_horizontal.comp, flip_error.comp) then compares the two, as linear RGB. Python:
// blurlab.metrics.gpu_hdr_flip; NumPy counterpart: flip-evaluator's "HDR" mode
// (blurlab.metrics.hdr_flip); test: tests/test_flip_gpu.py.
//
// The fit is t(x) = (k0 x² + k1 x) / (k3 x² + k4 x + k5) per channel, x = max(colour, 0) scaled.
// x is held below 1e15, where t has long reached 1 after the clip, so that x² stays finite.
#include "common/inputs.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D reference;
layout(binding = 1) uniform sampler2D test;
layout(binding = 0, rgba32f) uniform writeonly image2D reference_ldr;
layout(binding = 1, rgba32f) uniform writeonly image2D test_ldr;
uniform float exposure_scale;  // 2^exposure
uniform vec3 numerator;        // k0, k1, k2 of the fit
uniform vec3 denominator;      // k3, k4, k5

vec4 tone_mapped(sampler2D image, ivec2 p) {
    vec3 x = min(max(sanitize_color(texelFetch(image, p, 0)).rgb, 0.0) * exposure_scale, 1e15);
    vec3 top = (numerator.x * x + numerator.y) * x + numerator.z;
    vec3 bottom = (denominator.x * x + denominator.y) * x + denominator.z;
    return vec4(clamp(top / bottom, 0.0, 1.0), 1.0);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, textureSize(reference, 0)))) return;
    imageStore(reference_ldr, p, tone_mapped(reference, p));
    imageStore(test_ldr, p, tone_mapped(test, p));
}
