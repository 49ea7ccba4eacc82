#version 450
// The scatter dilation's last step (docs/spec.md §17.6, "Steps 1–2 by scatter"): each tile's
// two keys (common/reach_keys.glsl) name the source tiles whose half-motions it keeps; this
// pass writes those half-motions, prev (xy) and next (zw), as the gather dilation
// (passes/eevee_tile_dilate.glsl) writes its picks: the same bits. One invocation per tile.
// NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/reach_keys.glsl"

layout(binding = 0) uniform sampler2D tiles;
layout(binding = 1) uniform usampler2D reach_keys;

#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D dilated;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(tiles, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    imageStore(dilated, tile, resolved_reach(reach_keys, tiles, tile));
}
#endif
