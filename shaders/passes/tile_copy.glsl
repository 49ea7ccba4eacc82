#version 450
// The still class of the tile classification (docs/classify_and_steps.md): the output is the
// input color, as SPEC.md §3.4's early exit gives it. Run over the still tiles' list
// (TILE_LIST) or, without it, over the whole image. Compute only.
// NumPy twin: blurlab.reference.classify.classified (still tiles keep C).
#ifdef STAGE_COMPUTE
#include "common/tile_list.glsl"
layout(binding = 0) uniform sampler2D color;
layout(binding = 0, rgba32f) uniform writeonly image2D result;

void main() {
    ivec2 x = invocation_pixel();
    if (any(greaterThanEqual(x, textureSize(color, 0)))) return;
    imageStore(result, x, texelFetch(color, x, 0));
}
#endif
