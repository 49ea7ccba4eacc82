#version 450
// Zeroes the scatter dilation's keys (common/reach_keys.glsl) before the tile flatten offers
// into them: the keys texture comes from the context's pool with whatever it held.
#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r32ui) uniform writeonly uimage2D reach_keys;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(reach_keys)))) return;
    imageStore(reach_keys, p, uvec4(0u));
}
#endif
