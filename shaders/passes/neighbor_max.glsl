#version 450
// NeighborMax, docs/spec.md §3.3 (common/neighbor_max.glsl): one thread per tile (compute) or
// one fragment per tile. The compute backend of reconstruct_mcguire2012 and
// reconstruct_guertin2014 does not run this pass: their reconstruct pass computes NeighborMax
// in its prologue (common/tile_filter.glsl, FUSED_NEIGHBOR_MAX).
// NumPy twin: blurlab.twins.mcguire2012.neighbor_max.
#include "common/neighbor_max.glsl"

layout(binding = 0) uniform sampler2D tile_max;
uniform bool diagonal_reach;

#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32f) uniform writeonly image2D neighbor_max;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, textureSize(tile_max, 0)))) return;
    imageStore(neighbor_max, tile, vec4(neighbor_max_at(tile_max, tile, diagonal_reach), 0.0, 0.0));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec2 neighbor_max;

void main() {
    neighbor_max = neighbor_max_at(tile_max, ivec2(gl_FragCoord.xy), diagonal_reach);
}
#endif
