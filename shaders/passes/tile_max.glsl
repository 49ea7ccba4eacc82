#version 450
// TileMax, docs/spec.md §3.2: for each k x k tile (the last row and column may be partial), the
// half-vector of largest length among its pixels. Built as a compute shader (STAGE_COMPUTE) or a
// fragment shader (STAGE_FRAGMENT: one fragment per tile scans it all). The compute shader has
// two modes: for large tiles one 8 x 8 work group per tile, each thread scanning a strided part
// of it, then a reduction in shared memory; for small tiles (group_per_tile = false) one thread
// per tile, since a group per 4 x 4 tile leaves most threads idle and barriers cost llvmpipe
// dearly.
// NumPy twin: blurlab.twins.mcguire2012.tile_max.
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"

layout(binding = 0) uniform sampler2D motion;
uniform int k;
uniform float exposure;

// Largest-length half-vector over pixels origin + first + step * (i, j) inside tile and image.
vec2 scan(ivec2 tile, ivec2 first, int step) {
    ivec2 size = textureSize(motion, 0);
    ivec2 origin = tile * k;
    ivec2 end = min(origin + k, size);
    vec2 best = vec2(0.0);
    float best_length = -1.0;
    for (int y = origin.y + first.y; y < end.y; y += step) {
        for (int x = origin.x + first.x; x < end.x; x += step) {
            vec2 v = half_velocity(sanitize_motion(texelFetch(motion, ivec2(x, y), 0).xy), exposure, float(k));
            float l = length(v);
            if (l > best_length) {
                best = v;
                best_length = l;
            }
        }
    }
    return best;
}

#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32f) uniform writeonly image2D tile_max;
uniform bool group_per_tile;
shared vec3 candidates[64];  // xy: half-vector, z: its length

void main() {
    if (!group_per_tile) {
        ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
        if (any(greaterThanEqual(tile, imageSize(tile_max)))) return;
        imageStore(tile_max, tile, vec4(scan(tile, ivec2(0), 1), 0.0, 0.0));
        return;
    }
    // group_per_tile is a uniform: the barriers below stay in uniform control flow.
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    uint i = gl_LocalInvocationIndex;
    vec2 v = scan(tile, ivec2(gl_LocalInvocationID.xy), 8);
    candidates[i] = vec3(v, length(v));
    barrier();
    for (uint stride = 32u; stride > 0u; stride >>= 1u) {
        if (i < stride && candidates[i + stride].z > candidates[i].z) candidates[i] = candidates[i + stride];
        barrier();
    }
    if (i == 0u) imageStore(tile_max, tile, vec4(candidates[0].xy, 0.0, 0.0));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec2 tile_max;

void main() {
    tile_max = scan(ivec2(gl_FragCoord.xy), ivec2(0), 1);
}
#endif
