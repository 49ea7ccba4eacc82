#version 450
// HDR-FLIP's per-pixel error: the largest LDR-FLIP error over the exposures (docs/spec.md §6.2).
// Run once per exposure after flip_error.comp: `worst` keeps the running maximum (the first
// exposure sets it) and `partials` its sums per 16 x 16 work group, which the last exposure's
// run leaves for the mean. Python: blurlab.metrics.gpu_hdr_flip; test: tests/test_flip_gpu.py.

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D error;
layout(binding = 0, r32f) uniform image2D worst;
layout(binding = 1, r32f) uniform writeonly image2D partials;
uniform int first;  // 1 for the first exposure

shared float sums[256];

void main() {
    ivec2 size = imageSize(worst);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    float e = 0.0;
    if (all(lessThan(p, size))) {
        e = texelFetch(error, p, 0).r;
        if (first == 0) e = max(e, imageLoad(worst, p).r);
        imageStore(worst, p, vec4(e));
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
