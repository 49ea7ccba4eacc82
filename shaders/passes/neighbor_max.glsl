#version 450
// NeighborMax, docs/spec.md §3.3: for each tile, the TileMax of largest length among the 3 x 3 tiles
// around it; tiles outside the grid are skipped. Compute (one thread per tile) or fragment.
// With diagonal_reach (reconstruct_guertin2014, docs/guertin2014.md step 1), a diagonal tile
// counts only where its TileMax, extended both ways, can reach the center tile: both of its
// components point along the diagonal, (v.x dx)(v.y dy) > 0.
// NumPy twin: blurlab.twins.mcguire2012.neighbor_max.

layout(binding = 0) uniform sampler2D tile_max;
uniform bool diagonal_reach;

vec2 neighbor_max_at(ivec2 tile) {
    ivec2 grid = textureSize(tile_max, 0);
    vec2 best = vec2(0.0);
    float best_length = -1.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = tile + ivec2(dx, dy);
            if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, grid))) continue;
            vec2 v = texelFetch(tile_max, t, 0).xy;
            if (diagonal_reach && dx != 0 && dy != 0 && (v.x * dx) * (v.y * dy) <= 0.0) continue;
            if (length(v) > best_length) {
                best = v;
                best_length = length(v);
            }
        }
    }
    return best;
}

#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32f) uniform writeonly image2D neighbor_max;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, textureSize(tile_max, 0)))) return;
    imageStore(neighbor_max, tile, vec4(neighbor_max_at(tile), 0.0, 0.0));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec2 neighbor_max;

void main() {
    neighbor_max = neighbor_max_at(ivec2(gl_FragCoord.xy));
}
#endif
