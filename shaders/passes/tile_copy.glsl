#version 450
// The still class of the tile classification (docs/classify_and_steps.md): the output is the
// input color (sanitized as every pass reads it, docs/reliability.md), as docs/spec.md §3.4's early
// exit gives it. Run over the still tiles' list (TILE_LIST, with WHOLE_TILES: one work group
// per tile) or, without it, over the whole image. Compute only.
// NumPy twin: blurlab.twins.classify.classified (still tiles keep C).
#ifdef STAGE_COMPUTE
#include "common/inputs.glsl"
#include "common/tile_list.glsl"
layout(binding = 0) uniform sampler2D color;
layout(binding = 0, rgba32f) uniform writeonly image2D result;

#if defined(TILE_LIST) && defined(WHOLE_TILES)
void main() {
    ivec2 origin = listed_tile() * tile_list_k;
    ivec2 end = min(origin + tile_list_k, textureSize(color, 0));
    ivec2 first = origin + ivec2(gl_LocalInvocationID.xy);
    for (int y = first.y; y < end.y; y += 8) {
        for (int x = first.x; x < end.x; x += 8) {
            imageStore(result, ivec2(x, y), sanitize_color(texelFetch(color, ivec2(x, y), 0)));
        }
    }
}
#else
void main() {
    ivec2 x = invocation_pixel();
    if (any(greaterThanEqual(x, textureSize(color, 0)))) return;
    imageStore(result, x, sanitize_color(texelFetch(color, x, 0)));
}
#endif
#endif
