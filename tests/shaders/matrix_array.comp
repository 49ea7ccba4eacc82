#version 450
// dst = matrices[i] * src + offsets[i] with i = x % 2: arrays of mat4 and of floats as
// set_uniform sets them (matrices given row by row, as NumPy holds them).
#include "common/pixel.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly image2D src;
layout(binding = 1, rgba32f) uniform writeonly image2D dst;
uniform mat4 matrices[2];
uniform float offsets[2];

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (outside(p, imageSize(src))) return;
    int i = p.x % 2;
    imageStore(dst, p, matrices[i] * imageLoad(src, p) + offsets[i]);
}
