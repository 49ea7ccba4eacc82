#version 450
// A test pattern for `blurlab demo` and the foundation tests: a gradient in red and green, a
// checkerboard of CHECKER-pixel squares in blue, and rand(x, y, seed) (docs/spec.md §1) in alpha.
#include "common/pixel.glsl"
#include "common/random.glsl"

#ifndef CHECKER
#define CHECKER 16
#endif

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D pattern;
uniform uint seed;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(pattern);
    if (outside(p, size)) return;
    vec2 uv = (vec2(p) + 0.5) / vec2(size);
    float checker = float(((p.x / CHECKER) + (p.y / CHECKER)) % 2);
    imageStore(pattern, p, vec4(uv.x, uv.y, checker, rand(uint(p.x), uint(p.y), seed)));
}
