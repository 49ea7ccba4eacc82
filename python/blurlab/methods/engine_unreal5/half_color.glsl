#version 450
// engine_unreal5 step 4, docs/spec.md §17.7: the colour at half size, each texel the mean of
// a 2 x 2 block (the last row and column repeated where the size is odd). Compute, one
// invocation per half-size texel. NumPy twin: blurlab.twins.unreal5.half_color.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D half_color;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(half_color)))) return;
    ivec2 last = textureSize(color, 0) - 1;
    vec4 sum = vec4(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
            sum += sanitize_color(texelFetch(color, min(2 * p + ivec2(dx, dy), last), 0));
    imageStore(half_color, p, sum / 4.0);
}
