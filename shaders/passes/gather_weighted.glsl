#version 450
// gather_weighted, docs/spec.md §4 (ogldev tutorial 41): m = M/2; taps at X, X - m, X - 2m, X - 3m
// with weights 0.4, 0.3, 0.2, 0.1. Instant t1. Compute (default) or fragment (the tutorial's).
// NumPy twin: blurlab.reference.gathers.gather_weighted.
#include "common/gather.glsl"

vec4 gather_weighted_at(ivec2 x) {
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * 0.5;
    vec2 center = vec2(x) + 0.5;
    const float weights[4] = float[](0.4, 0.3, 0.2, 0.1);
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < 4; ++i) add_tap(center - float(i) * m, weights[i], sum, total);
    return sum / total;  // the center tap is always inside: total >= 0.4
}

#ifdef STAGE_COMPUTE
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D result;
void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, textureSize(color, 0)))) return;
    imageStore(result, x, gather_weighted_at(x));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec4 result;
void main() {
    result = gather_weighted_at(ivec2(gl_FragCoord.xy));
}
#endif
