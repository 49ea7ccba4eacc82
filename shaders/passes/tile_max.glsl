#version 450
// TileMax, docs/spec.md §3.2: for each k x k tile (the last row and column may be partial), the
// half-vector of largest length among its pixels; among equal lengths, the first pixel in row
// order (the NumPy twin's argmax). Built as a compute shader (STAGE_COMPUTE) or a fragment shader
// (STAGE_FRAGMENT: one fragment per tile scans it all). The compute shader has two modes: for
// small tiles (group_per_tile = false) one thread per tile, since a group per 4 x 4 tile leaves
// most threads idle and barriers cost llvmpipe dearly; for large tiles one work group per tile,
// each thread scanning part of it, then a reduction. The group's layout is a variant (§3.2,
// blurlab.methods.tile_filter.TILE_MAX_VARIANTS), measured by `blurlab bench layouts`:
//   default           8 x 8 threads, thread (i, j) scans pixels (i + 8a, j + 8b), shared-memory
//                     reduction in 6 barrier steps;
//   TILE_MAX_THREADS  N threads in a row, thread t scans the pixels t, t + N, ... of the tile in
//                     row order (neighbouring threads read neighbouring pixels), shared-memory
//                     reduction in log2 N steps; with TILE_MAX_SUBGROUP, where the driver has
//                     GL_KHR_shader_subgroup_arithmetic and _ballot, a subgroup reduction and one
//                     barrier instead (without them, the shared-memory one).
// Every mode picks as common/group_pick.glsl says, so all give the same bits.
// NumPy twin: blurlab.twins.mcguire2012.tile_max.
#define PICK_SLOTS 1
#ifdef TILE_MAX_THREADS
#define PICK_ROWS TILE_MAX_THREADS
#else
#define PICK_GRID_SIDE 8
#endif
#ifdef TILE_MAX_SUBGROUP
#define PICK_SUBGROUP 1
#endif
#include "common/group_pick.glsl"
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/length_key.glsl"

layout(binding = 0) uniform sampler2D motion;
uniform int k;
uniform float exposure;

void consider(ivec2 tile, ivec2 p, uint index) {
    vec2 v = half_velocity(sanitize_motion(texelFetch(motion, tile * k + p, 0).xy), exposure, float(k));
    offer(0, v, length_key(length(v)), index);
}

// The tile's extent inside the image.
ivec2 tile_extent(ivec2 tile) {
    return min(tile * k + k, textureSize(motion, 0)) - tile * k;
}

#ifdef STAGE_COMPUTE
layout(binding = 0, rg32f) uniform writeonly image2D tile_max;

void main() {
    ivec2 tile;
    if (pick_tile(imageSize(tile_max), tile)) imageStore(tile_max, tile, vec4(picks[0].v, 0.0, 0.0));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec2 tile_max;

void main() {
    clear_picks();
    ivec2 tile = ivec2(gl_FragCoord.xy);
    scan_grid(tile, tile_extent(tile), ivec2(0), 1);
    tile_max = picks[0].v;
}
#endif
