#version 450
// Squared-error reduction for sweeps, docs/spec.md §6: the sum over pixels and RGB channels of
// (clamp(a, 0, 1) - clamp(b, 0, 1))^2, one partial sum per 16 x 16 work group (written to a
// buffer and added up in double precision on the CPU), so a sweep reads back a few kilobytes
// instead of two images. NumPy twin: blurlab.metrics.mse.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D image_a;
layout(binding = 1) uniform sampler2D image_b;
layout(std430, binding = 0) writeonly buffer Partials { float partials[]; };
shared float sums[256];

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    uint i = gl_LocalInvocationIndex;
    float e = 0.0;
    if (all(lessThan(p, textureSize(image_a, 0)))) {
        vec3 d = clamp(texelFetch(image_a, p, 0).rgb, 0.0, 1.0) - clamp(texelFetch(image_b, p, 0).rgb, 0.0, 1.0);
        e = dot(d, d);
    }
    sums[i] = e;
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1u) {
        if (i < stride) sums[i] += sums[i + stride];
        barrier();
    }
    if (i == 0u) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = sums[0];
}
