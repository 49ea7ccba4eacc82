#version 450
// dst = src + value, per texel: the smallest compute pass the foundation tests check.
#include "common/pixel.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly image2D src;
layout(binding = 1, rgba32f) uniform writeonly image2D dst;
uniform float value;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (outside(p, imageSize(src))) return;
    imageStore(dst, p, imageLoad(src, p) + value);
}
