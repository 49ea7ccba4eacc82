#version 450
// Accumulation, docs/spec.md §1 "Reference": sum += weight * color, in float32, one sub-frame at a
// time. With weight 1/N over N sub-frames the sum is their mean.
// NumPy twin: blurlab.twins.sub_frames.mean_of_renders.
#include "common/inputs.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D color;
layout(binding = 0, rgba32f) uniform image2D sum;
uniform float weight;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(sum)))) return;
    imageStore(sum, p, imageLoad(sum, p) + weight * sanitize_color(texelFetch(color, p, 0)));
}
