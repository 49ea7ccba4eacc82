// The entry points every post-process pass with one RGBA32F (or HALF_RESULT: RGBA16F) output
// shares. Before including this file a pass defines PASS_AT to its per-pixel function
// (vec4 f(ivec2 x)) and declares a sampler2D `color` of the output's size. Compute
// (STAGE_COMPUTE): one invocation per pixel, 16 x 16 per work group, written to image `result`;
// fragment (STAGE_FRAGMENT): one fragment per pixel of the framebuffer, written to output
// `result`. A pass may define PASS_PROLOGUE to a function that every invocation of a compute
// work group runs before its bounds test (one with a barrier, common/tile_filter.glsl).
// With HALF_RESULT (the tile filters' half_result) the output is RGBA16F, each value rounded by
// common/half_float.glsl before the store, so that no driver's own rounding enters.
#ifdef HALF_RESULT
#include "common/half_float.glsl"
vec4 stored_result(vec4 v) {
    return round_to_half(v);
}
#else
vec4 stored_result(vec4 v) {
    return v;
}
#endif

#ifdef STAGE_COMPUTE
layout(local_size_x = 16, local_size_y = 16) in;
#ifdef HALF_RESULT
layout(binding = 0, rgba16f) uniform writeonly image2D result;
#else
layout(binding = 0, rgba32f) uniform writeonly image2D result;
#endif

void main() {
#ifdef PASS_PROLOGUE
    PASS_PROLOGUE();
#endif
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, textureSize(color, 0)))) return;
    imageStore(result, x, stored_result(PASS_AT(x)));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec4 result;

void main() {
    result = stored_result(PASS_AT(ivec2(gl_FragCoord.xy)));
}
#endif
