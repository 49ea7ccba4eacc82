#version 450
// engine_eevee step 2, docs/spec.md §17.2: each tile's motion dilated into the tiles it reaches.
// EEVEE scatters a conservative rasterization of each tile's motion line; this pass gathers the
// same result: each tile D looks at every tile S within reach and keeps, per side, the longest
// half-motion whose line meets D's widened square (common/tile_dilate.glsl); the first S in
// row-major order among equal lengths (compared as common/tile_pick.glsl's pick_key says: exact
// for engine_eevee). Compute, two modes (uniform group_per_tile): a work group per tile whose
// invocations share the sources in reach, then merge their picks (common/tile_pick.glsl,
// layouts TILE_PICK_VARIANTS); or one invocation per tile looking at them all. All give the
// same bits. gather_coverage may run the same dilation in its gather's prologue instead
// (common/coverage_dilation.glsl). NumPy twin: blurlab.twins.eevee.tile_dilate.
#include "common/tile_pick.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform int tile_size;
uniform float reach_limit;  // px: half-motions are clamped to it (engine_eevee's max_blur)

#include "common/tile_dilate.glsl"

vec4 source_motion(ivec2 source) {
    return texelFetch(tiles, source, 0);
}

layout(binding = 0, rgba32f) uniform writeonly image2D dilated;

void store_pick(ivec2 tile, vec4 pick) {
    imageStore(dilated, tile, pick);
}

void main() {
    pick_tiles(textureSize(tiles, 0));
}
